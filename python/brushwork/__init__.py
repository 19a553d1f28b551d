"""brushwork: the expressive virtual Chinese brush of Chu and Tai (2004), and what it leaves on paper."""
from ._core import BrushModel, MeshOptions, StepStats
from .brush import Brush, Pose

__all__ = ["Brush", "BrushModel", "MeshOptions", "Pose", "StepStats"]
__version__ = "0.1.0"
