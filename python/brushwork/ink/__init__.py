"""The ink as geometry, out of the paper: outlines in mm as SVG or PDF."""
from .vectors import VECTOR_FORMATS, pdf_bytes, svg_text, write_vectors

__all__ = ["VECTOR_FORMATS", "pdf_bytes", "svg_text", "write_vectors"]
