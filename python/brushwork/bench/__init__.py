"""Benchmarks for brushwork: solver robustness (`stability`), solver speed (`solver`), and report helpers."""
