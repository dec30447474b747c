"""``flexgear bench cms``: Craig-Bampton reduction benchmark, side by side with Exudyn.

For each component (pinion, wheel, carrier from ``fe_components.reference``) and
mesh size: build the P2 model, tie every interface to a 6-DOF master by RBE2
(``fe_components.coupling.couple``), and in separate child processes (so each
peak RSS is its own):

* ``cms``: :class:`cms.craig_bampton.CraigBamptonReductor` on (K_c, M_c, masters);
* ``bare``: one factorization of K_ii plus the block solves CB needs at the least
  (n_boundary constraint-mode right-hand sides + one block of n_modes): the floor
  any Craig-Bampton implementation on this factorization pays;
* ``bare_as_solved``: the same factorization and constraint block, plus exactly the
  solves cms's eigen phase made (same count and widths, on random vectors), timed
  without the eigensolver around them: what the linear algebra alone costs, so
  cms / this ratio is the implementation's overhead;
* ``full``: the coupled model's free-free modes (shift-invert, sigma < 0) as the
  reference for the superelement's frequency error;
* ``exudyn``: ``FEMinterface.ComputeHurtyCraigBamptonModes`` (RBE2 static modes,
  ``excludeRigidBodyMotion=False``) on the same full K, M and interface node
  sets. Its basis spans exactly the CB space of the RBE2-coupled model, and its
  fixed-interface eigenvalues are those of the same K_ii, so both the fixed-
  interface frequencies and the reduced free-free frequencies must agree.

Prints a markdown table on stdout. Times in s, memory = peak RSS
of the child process in GB (includes its copy of the model).
"""
from __future__ import annotations

import argparse
import logging
import multiprocessing as mp
import os
import resource
import sys
import time
import traceback

import numpy as np
import scipy.linalg as sla

log = logging.getLogger(__name__)

N_COMPARE = 10        # elastic free-free frequencies compared
# Both codes solve the same fixed-interface eigenproblem (K_ii, M_ii), so their frequencies may
# differ only by solver round-off; 1e-6 relative is the acceptance threshold of the comparison.
AGREE_RTOL = 1e-6


# ----------------------------------------------------------------- model set-up
def _components():
    from fe_components import reference as ref
    return {"pinion": ref.PINION_SMOOTH, "wheel": ref.WHEEL_SMOOTH, "carrier": ref.CARRIER}


def build(name: str, size: float, cache_dir: str | None):
    from fe_components.coupling import couple
    from fe_components.fe_model import build_component
    model = build_component(_components()[name], mesh_size=size, cache_dir=cache_dir)
    c = couple(model, {k: "rbe2" for k in model.interfaces})
    return model, c, c.dof_layout(model.nodes), c.boundary_names


# ----------------------------------------------------------------- child jobs
def _job_cms(model, c, layout, names, n_modes):
    from cms.craig_bampton import CraigBamptonReductor, SolverOptions
    red = CraigBamptonReductor(c.K_c, c.M_c, c.boundary_dofs, n_modes=n_modes,
                               dof_layout=layout, dof_names=names,
                               options=SolverOptions(threads=1, factor_threads=None))
    se = red.reduce()
    lam = sla.eigh(se.K, se.M, eigvals_only=True)
    t = red.timings
    return {"factorize": t.factorize, "constraint": t.constraint_modes, "eigen": t.eigen,
            "total": t.total, "fixed_hz": se.mode_frequencies_hz, "reduced_lam": lam,
            "n_boundary": se.n_boundary, "n_interior": len(se.interior_dofs),
            "checks": se.metadata["self_checks"], "backend": se.metadata["solver"]["backend"],
            "eigen_solves": se.metadata["solver"]["eigen_solves"],
            "eigen_rhs": se.metadata["solver"]["eigen_rhs"]}


def _interior_blocks(c):
    """(interior DOF count, K_ii as CSC, K_ib dense) of the coupled model."""
    b = c.boundary_dofs
    mask = np.ones(c.K_c.shape[0], bool)
    mask[b] = False
    i = np.flatnonzero(mask)
    return len(i), c.K_c[i][:, i].tocsc(), c.K_c[i][:, b].toarray()


def _job_bare(model, c, layout, names, n_modes, eigen_solves=1, eigen_rhs=None):
    """Factorization of K_ii, the constraint-mode block, then ``eigen_solves`` solves of
    ``eigen_rhs / eigen_solves`` random columns each. Defaults: one block of ``n_modes``
    (the floor); with cms's counts: the solves its eigen phase made (ARPACK: one vector
    per call)."""
    from cms.linsolve import factor
    ni, Kii, Kib = _interior_blocks(c)
    eigen_rhs = n_modes if eigen_rhs is None else eigen_rhs
    width = max(1, round(eigen_rhs / max(eigen_solves, 1)))
    rng = np.random.default_rng(0)
    t0 = time.perf_counter()
    F = factor(Kii)
    F.threads = 1
    F.solve(Kib)
    for _ in range(eigen_solves):
        F.solve(rng.standard_normal((ni, width)) if width > 1 else rng.standard_normal(ni))
    return {"total": time.perf_counter() - t0, "factorize": F.seconds}


def _job_full(model, c, layout, names, n_modes):
    from cms.eigen import lowest_modes
    K, M = c.K_c, c.M_c
    # shift below the rigid modes: -(2 pi 1 Hz)^2 is far below the first elastic
    # mode of steel parts of this size (> 100 Hz) and makes K - sigma M definite
    sigma = -(2 * np.pi * 1.0) ** 2
    # K - sigma M has condition ~ lambda_max / |sigma| ~ 1e13, which limits the elastic
    # Ritz vectors to eta ~ 1e-5; the Ritz VALUES are then still accurate to
    # ~ eta^2 relative (Rayleigh quotient), far below the errors reported here.
    r = lowest_modes(K, M, 6 + N_COMPARE, sigma=sigma, threads=1, tol=1e-4)
    return {"lam": r.eigenvalues, "residual": float(r.residuals.max()), "total": r.seconds}


def _job_exudyn(model, c, layout, names, n_modes):
    import exudyn.FEM as xfem
    fem = xfem.FEMinterface()
    fem.stiffnessMatrix = model.K.tocsr()
    fem.massMatrix = model.M.tocsr()
    fem.nodes = {"Position": np.ascontiguousarray(model.nodes)}
    bnl = [np.asarray(model.interfaces[n].nodes).tolist() for n, _, _ in c.masters]
    t0 = time.perf_counter()
    fem.ComputeHurtyCraigBamptonModes(bnl, n_modes, useSparseSolver=True,
                                      computationMode=xfem.HCBstaticModeSelection.RBE2,
                                      excludeRigidBodyMotion=False, timerTreshold=10**12)
    dt = time.perf_counter() - t0
    V = fem.modeBasis["matrix"]
    Kr = V.T @ (model.K @ V)
    Mr = V.T @ (model.M @ V)
    lam_r = sla.eigh(0.5 * (Kr + Kr.T), 0.5 * (Mr + Mr.T), eigvals_only=True)
    lam = np.sort(np.asarray(fem.eigenValues))      # |omega^2| of the fixed-interface modes
    return {"total": dt, "fixed_hz": np.sqrt(lam) / (2 * np.pi), "reduced_lam": lam_r}


JOBS = {"cms": _job_cms, "bare": _job_bare, "bare_as_solved": _job_bare,
        "full": _job_full, "exudyn": _job_exudyn}


def _child(job, args, conn, mem_limit_gb):
    try:
        if mem_limit_gb:
            lim = int(mem_limit_gb * 2**30)
            resource.setrlimit(resource.RLIMIT_AS, (lim, lim))
        *positional, extra = args
        out = JOBS[job](*positional, **extra)
        out["peak_gb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
        conn.send(("ok", out))
    except BaseException as exc:  # report any failure (MemoryError included) to the parent
        conn.send(("error", f"{type(exc).__name__}: {exc}\n{traceback.format_exc(limit=3)}"))
    finally:
        conn.close()


def run_job(job, args, timeout, mem_limit_gb=None):
    ctx = mp.get_context("fork")
    parent, child = ctx.Pipe(duplex=False)
    p = ctx.Process(target=_child, args=(job, args, child, mem_limit_gb))
    t0 = time.perf_counter()
    p.start()
    child.close()
    status, out = "timeout", None
    if parent.poll(timeout):
        try:
            status, out = parent.recv()
        except EOFError:
            status, out = "error", "child died (killed / out of memory?)"
    p.join(5)
    if p.is_alive():
        p.kill()   # only the child this function started
        p.join()
    wall = time.perf_counter() - t0
    if status != "ok":
        log.warning("%s: %s after %.0f s: %s", job, status, wall, out)
    return status, out, wall


# ----------------------------------------------------------------- table
def _rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    n = min(len(a), len(b))
    return float(np.max(np.abs(a[:n] / b[:n] - 1))) if n else float("nan")


def _hz(lam):
    return np.sqrt(np.clip(lam, 0, None)) / (2 * np.pi)


HEADER = ("| component | DOFs | boundary DOFs | modes | factorize s | constraint s | eigen s "
          "| total s | peak GB | freq err vs full FE | Exudyn s | Exudyn/cms | Exudyn peak GB "
          "| max rel diff vs Exudyn (fixed-if / reduced) | eigen solves | bare floor s | cms/floor "
          "| bare as solved s | cms/as solved |")
SEP = "|" + "---|" * (HEADER.count("|") - 1)


def row(name, n, res):
    cm, bare, full, ex = (res.get(k) for k in ("cms", "bare", "full", "exudyn"))
    if cm is None:
        return f"| {name} | {n} | | | | | | failed |" + " |" * (HEADER.count("|") - 9)
    err = "n/a"
    if full is not None:
        err = "%.2e" % _rel(_hz(cm["reduced_lam"][6:6 + N_COMPARE]), _hz(full["lam"][6:]))
    ex_t = ex_r = ex_m = agree = "n/a"
    if isinstance(ex, dict):
        ex_t, ex_r, ex_m = "%.1f" % ex["total"], "%.1f" % (ex["total"] / cm["total"]), "%.1f" % ex["peak_gb"]
        agree = "%.1e / %.1e" % (_rel(cm["fixed_hz"], ex["fixed_hz"]),
                                 _rel(_hz(cm["reduced_lam"][6:6 + N_COMPARE]),
                                      _hz(ex["reduced_lam"][6:6 + N_COMPARE])))
    elif isinstance(ex, str):
        ex_t = ex
    bt = br = at = ar = "n/a"
    if bare is not None:
        bt, br = "%.1f" % bare["total"], "%.2f" % (cm["total"] / bare["total"])
    aso = res.get("bare_as_solved")
    if aso is not None:
        at, ar = "%.1f" % aso["total"], "%.2f" % (cm["total"] / aso["total"])
    return (f"| {name} | {n} | {cm['n_boundary']} | {len(cm['fixed_hz'])} | {cm['factorize']:.1f} "
            f"| {cm['constraint']:.1f} | {cm['eigen']:.1f} | {cm['total']:.1f} | {cm['peak_gb']:.1f} "
            f"| {err} | {ex_t} | {ex_r} | {ex_m} | {agree} | {cm['eigen_solves']} | {bt} | {br} "
            f"| {at} | {ar} |")


#: mesh sizes (m): about 20-50k, 35-125k and >= 300k coupled DOFs per component
DEFAULT_SIZES = {"pinion": (0.0083, 0.0056, 0.003), "wheel": (0.0096, 0.0066, 0.004),
                 "carrier": (0.013, 0.009, 0.0062)}


def _sizes_for(name: str, spec: str | None) -> list[float]:
    """Mesh sizes (m) for ``name`` from ``"0.01,0.005"`` (all components) or
    ``"pinion=0.003,wheel=0.004"`` (per component); default :data:`DEFAULT_SIZES`."""
    if not spec:
        return list(DEFAULT_SIZES[name])
    if "=" not in spec:
        return [float(x) for x in spec.split(",")]
    out = [float(v) for k, v in (item.split("=") for item in spec.split(",")) if k == name]
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="flexgear bench cms", description=__doc__.split("\n")[0])
    ap.add_argument("--components", default="pinion,wheel,carrier")
    ap.add_argument("--sizes", default=None,
                    help="mesh sizes in m: '0.01,0.005' for every component or "
                         "'pinion=0.003,wheel=0.004' per component "
                         "(default: three per component, up to >= 300k DOFs)")
    ap.add_argument("--modes", type=int, default=30)
    ap.add_argument("--no-exudyn", action="store_true")
    ap.add_argument("--no-full", action="store_true")
    ap.add_argument("--timeout", type=float, default=1800.0, help="per job, s")
    ap.add_argument("--exudyn-timeout", type=float, default=600.0, help="Exudyn job, s")
    ap.add_argument("--exudyn-mem-gb", type=float, default=14.0,
                    help="address-space limit of the Exudyn child (protects the machine)")
    ap.add_argument("--cache-dir", default=None, help="mesh cache (fe_components default if unset)")
    ap.add_argument("--out", default=None, help="also write the table to this markdown file")
    a = ap.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s %(message)s")
    from threadpoolctl import threadpool_info
    blas = sorted({i["filepath"] for i in threadpool_info() if i.get("user_api") == "blas"})
    log.info("BLAS libraries loaded: %s", blas)
    jobs = ["cms", "bare", "bare_as_solved"] + ([] if a.no_full else ["full"]) + ([] if a.no_exudyn else ["exudyn"])
    if "exudyn" in jobs:
        try:
            import exudyn  # noqa: F401
        except ImportError:
            log.warning("exudyn not installed (extra [bench]); skipping the comparison")
            jobs.remove("exudyn")
    lines = [HEADER, SEP]
    print(HEADER, SEP, sep="\n", flush=True)
    for name in a.components.split(","):
        sizes = _sizes_for(name, a.sizes)
        for h in sizes:
            t0 = time.perf_counter()
            model, c, layout, names = build(name, h, a.cache_dir)
            log.info("%s h=%g m: %d DOFs (coupled %d), built in %.1f s", name, h, model.n_dofs,
                     c.K_c.shape[0], time.perf_counter() - t0)
            res = {}
            for job in jobs:
                extra = {}
                if job == "bare_as_solved":
                    if not isinstance(res.get("cms"), dict):
                        continue
                    extra = {k: res["cms"][k] for k in ("eigen_solves", "eigen_rhs")}
                status, out, wall = run_job(job, (model, c, layout, names, a.modes, extra),
                                            a.exudyn_timeout if job == "exudyn" else a.timeout,
                                            a.exudyn_mem_gb if job == "exudyn" else None)
                res[job] = out if status == "ok" else (f"{status} ({wall:.0f} s)" if job == "exudyn" else None)
                if status == "ok":
                    log.info("%s %s: %.1f s, peak %.1f GB", name, job, out["total"], out["peak_gb"])
            line = row(name, c.K_c.shape[0], res)
            lines.append(line)
            print(line, flush=True)
            if isinstance(res.get("exudyn"), dict) and isinstance(res.get("cms"), dict):
                d = _rel(res["cms"]["fixed_hz"], res["exudyn"]["fixed_hz"])
                if not d <= AGREE_RTOL:
                    log.error("%s: fixed-interface frequencies differ from Exudyn by %.2e > %g",
                              name, d, AGREE_RTOL)
            if a.out:
                tmp = a.out + ".tmp"
                with open(tmp, "w") as fh:
                    fh.write("\n".join(lines) + "\n")
                os.replace(tmp, a.out)
            del model, c
    return 0


if __name__ == "__main__":
    sys.exit(main())
