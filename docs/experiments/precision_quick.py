"""Quick look at the shipped default (or an override) on the precision motions at 1x.

    cd <repo> && PYTHONPATH=python OPENBLAS_NUM_THREADS=1 \
        python3 docs/experiments/precision_quick.py [--gaps] [field=value ...]

The same medians as `brushwork bench precision` reports for one of our rows (its functions, its
valid frames), without the peers, the sweeps or the ink column: time per frame (least of 3
runs), iterations, share of frames at q_max, KKT, energy gap (--gaps: the Newton polish of every
frame, slower), skeleton and footprint errors against the reference.  The references are
solved once and kept in $BW_REF_CACHE (default /tmp/brushwork_refs.pkl); delete it after a
change of the model or of the reference solver.  field=value: BrushModel overrides, e.g.
friction_curvature=True q_max=10.
"""
import os
import pickle
import sys

import numpy as np

from brushwork.bench import precision as P


def parse(v: str):
    if v in ("True", "False"):
        return v == "True"
    return float(v) if any(ch in v for ch in ".e") else int(v)


def main() -> None:
    over = [(k, parse(v)) for k, v in (a.split("=") for a in sys.argv[1:] if not a.startswith("--"))]
    cache = os.environ.get("BW_REF_CACHE", "/tmp/brushwork_refs.pkl")
    if os.path.exists(cache):
        with open(cache, "rb") as fh:
            refs = pickle.load(fh)
    else:
        refs = {mo.name: P.run_reference(mo, mo.poses(1.0), [], lambda s: print(s, file=sys.stderr))
                for mo in P.motions(False)}
        with open(cache, "wb") as fh:
            pickle.dump(refs, fh)
    t, its, conv, kk, sk, fe, gaps = [], [], [], [], [], [], []
    for mo in P.motions(False):
        model = P._model_for(mo, over)
        poses = mo.poses(1.0)
        tr = P.run_ours(model, poses, 3)
        ref = refs[mo.name]
        v = ref.valid
        if "--gaps" in sys.argv:
            gaps += list(np.abs(P.own_problem_gaps(model, poses)[v]))
        t += list(tr.times[v])
        its += list(tr.iterations[v])
        conv += list(tr.converged[v])
        kk += list(tr.kkt[v])
        for k in np.flatnonzero(v):
            sk.append(P.skeleton_error(tr.skeletons[k], ref.skeletons[k]))
            fe.append(P.footprint_error(tr.footprints[k], ref.footprints[k]))
        print(f"  {mo.name:40s} it/frame {np.mean(tr.iterations):5.2f}  at q_max "
              f"{100 * np.mean(tr.iterations >= model.q_max):5.1f}%  KKT p50 {np.median(tr.kkt):.2e}",
              file=sys.stderr)
    its = np.array(its)
    q_max = dict(over).get("q_max", P.BrushModel.preset("medium").q_max)
    print(f"overrides {over}: {len(t)} frames, ms/frame p50 {1e3 * np.median(t):.4f} p95 "
          f"{1e3 * np.percentile(t, 95):.4f}; it/frame {its.mean():.2f} (p50 {np.median(its):g}), "
          f"at q_max {100 * np.mean(its >= q_max):.1f}%, unconverged {100 * (1 - np.mean(conv)):.0f}%; "
          f"KKT p50 {np.median(kk):.2e}, energy gap p50 "
          f"{np.nanmedian(gaps) if gaps else float('nan'):.2e}, skeleton p50 {np.median(sk):.3f} mm, "
          f"footprint p50 {np.median(fe):.4f}; us/iteration {1e6 * np.sum(t) / max(its.sum(), 1):.2f}")


if __name__ == "__main__":
    main()
