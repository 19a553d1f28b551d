"""brushwork: the expressive virtual Chinese brush of Chu and Tai (2004), and what it leaves on paper."""
from ._core import BrushModel, BrushState, DepositStats, Ink, MeshOptions, StepStats
from .brush import Brush, Pose
from .paper import Paper, VectorPaper, make_paper, render_info
from .scene import Scene
from .view import BrushView

__all__ = ["Brush", "BrushModel", "BrushState", "BrushView", "DepositStats", "Ink", "MeshOptions", "Paper", "Pose", "Scene",
           "VectorPaper", "make_paper",
           "StepStats", "render_info"]
__version__ = "0.1.0"
