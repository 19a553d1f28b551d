"""Work-precision benchmark: the recorded motions and the solver settings swept."""
from __future__ import annotations

from dataclasses import dataclass


from ... import BrushModel
from ...recorded import flick, press_drag_turn_lift
from .config import Q_MAX_SWEEP, RATE_SWEEP, TOL_SWEEP


@dataclass(frozen=True)
class Motion:
    """One recorded motion on one brush: `kind` "pdtl" (press_drag_turn_lift) or "flick",
    `frames` poses at rate 1."""
    kind: str
    preset: str
    exponent: float
    frames: int

    @property
    def name(self) -> str:
        what = {"pdtl": "press-drag-turn-lift", "flick": "flick"}[self.kind]
        return f"{what} {self.preset} m={self.exponent:g}"

    def model(self) -> BrushModel:
        m = BrushModel.preset(self.preset)
        m.exponent = self.exponent
        return m

    def poses(self, rate: float = 1.0) -> list:
        """The motion's poses, resampled to `rate` times as many per stroke."""
        n = max(1, int(round(self.frames * rate)))
        if self.kind == "pdtl":
            return press_drag_turn_lift(self.model(), frames=max(n, 50))
        return flick(self.model(), frames=max(n, 20))


@dataclass(frozen=True)
class Setting:
    """A setting of ours: `family` is q_max, tolerance, hessian, rate or float; `overrides` the
    BrushModel fields it changes from the shipped default; `rate` the poses-per-stroke factor."""
    label: str
    family: str
    overrides: tuple = ()
    rate: float = 1.0
    default: bool = False


def stiffest_and_softest() -> tuple[str, str]:
    """The presets with the stiffest and the softest tip (tip kappa = bend_stiffness /
    stiffness_ratio, N*mm/rad^m)."""
    tip = {p: BrushModel.preset(p).bend_stiffness / BrushModel.preset(p).stiffness_ratio
           for p in BrushModel.presets()}
    return max(tip, key=tip.get), min(tip, key=tip.get)


def motions(quick: bool) -> list[Motion]:
    """The recorded motions: quick = one short stroke on the shipped `medium` brush."""
    if quick:
        return [Motion("pdtl", "medium", 2.0, 50)]
    stiff, soft = stiffest_and_softest()
    return [Motion(kind, preset, m, frames)
            for preset in (stiff, soft) for m in (2.0, 3.0)
            for kind, frames in (("pdtl", 120), ("flick", 40))]


def settings(quick: bool) -> list[Setting]:
    """Our settings: the q_max sweep at the shipped tolerance (its shipped q_max row is the
    default), the tolerance sweep at the shipped q_max, a fresh Hessian, the frame rates, float."""
    shipped = BrushModel.preset("medium")
    qs = sorted(set(Q_MAX_SWEEP) | {shipped.q_max})
    tols = sorted(set(TOL_SWEEP) - {shipped.tolerance}, reverse=True)
    rates = RATE_SWEEP
    if quick:
        qs = [q for q in qs if q in (1, 3, 10, shipped.q_max, 50)]
        tols = [t for t in tols if t in (1e-3, 1e-8)]
        rates = (2.0,)
    out = [Setting(f"q_max={q}", "q_max", (("q_max", q),), default=q == shipped.q_max) for q in qs]
    out += [Setting(f"tol={t:.0e}", "tolerance", (("tolerance", t),)) for t in tols]
    out.append(Setting("fresh Hessian", "hessian", (("warm_hessian", False),)))
    out += [Setting(f"{r:g}x poses", "rate", rate=r) for r in rates]
    out.append(Setting("float", "float"))
    return out


def default_label() -> str:
    """The shipped setting, spelled out."""
    m = BrushModel.preset("medium")
    return (f"q_max={m.q_max}, tol={m.tolerance:.0e}, "
            f"{'carried' if m.warm_hessian else 'fresh'} Hessian, double, 1x poses")
