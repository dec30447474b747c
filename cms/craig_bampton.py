"""Craig-Bampton reductor: static constraint modes + fixed-interface normal modes.

    u = [u_b; u_i] = [[I, 0], [Psi, Phi]] [q_b; q_m]
    Psi = -K_ii^{-1} K_ib                 (all boundary columns in ONE block solve)
    K_ii Phi = M_ii Phi diag(omega^2)     (shift-invert on the SAME factorization)
    Phi^T M_ii Phi = I

Reduced matrices are the Galerkin projection K_r = T^T K T, M_r = T^T M T of the
basis T above, formed with explicit sparse products; in exact arithmetic
K_r = [[K_bb + K_ib^T Psi, 0], [0, diag(omega^2)]] and the modal mass block is I.

Guyan (static) reduction is the case ``n_modes=0``.

Rigid-body information (optional but recommended), one of:
``node_coords`` (n/3 x 3, plain solid DOFs ordered 3*node + xyz, m);
``dof_layout = (points (n, 3), kinds (n,))`` for models with 6-DOF master nodes
(kinds 0..5 = ux, uy, uz, rx, ry, rz; see :mod:`cms.rigid`);
or an explicit ``rigid_body_basis`` (n x 6, columns [tx, ty, tz, rx, ry, rz]).
The first two also give the interface geometry stored in the superelement. With any
of them the reductor names a mechanism before factorising, checks K R = 0, and records
the reduced vs full rigid-body mass matrix (mass, first moments, inertia about the
origin).

Solver settings (backend, threads, tolerance, ordering, eigen method) are one
:class:`SolverOptions` value.
"""
from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from . import rigid
from .eigen import lowest_modes
from .errors import InteriorMechanismError, ModeLimitError, ReductionError
from .linsolve import factor, thread_limit
from .superelement import Superelement

log = logging.getLogger(__name__)

#: Relative residual allowed for the constraint-mode solve ||K_ii Psi + K_ib|| / ||K_ib||.
CONSTRAINT_RESIDUAL_TOL = 1e-8
#: Relative size of ||K R|| / (||K||_1 ||R||) above which the rigid basis is rejected.
RIGID_BASIS_TOL = 1e-8


@dataclass
class Timings:
    factorize: float = 0.0
    constraint_modes: float = 0.0
    eigen: float = 0.0
    assemble: float = 0.0
    total: float = 0.0


@dataclass(frozen=True)
class SolverOptions:
    """How a reduction is computed (linear solver, threads, eigen solver and its tolerance),
    as opposed to what is reduced (the reductor's other arguments).

    backend : linear solver backend (``"cholmod"``, ``"scipy"`` or ``None`` = best).
    threads : BLAS/OpenMP thread limit during the solves and the eigen solve (1 was
        6x faster than 2 for shift-invert ARPACK at 30k DOFs on this 2-core machine);
        ``None`` leaves the default.
    factor_threads : thread limit during the factorization (``None``: all cores, which
        helps the supernodal BLAS-3 work when CHOLMOD is linked to a threaded BLAS).
    tol : relative eigen-residual tolerance.
    ordering : CHOLMOD fill-reducing ordering (default METIS).
    eigen_method : ``"arpack"`` or ``"block"`` (see :func:`cms.eigen.lowest_modes`).
    """

    backend: str | None = None
    threads: int | None = None
    factor_threads: int | None = None
    tol: float = 1e-8
    ordering: str = "metis"
    eigen_method: str = "arpack"


class CraigBamptonReductor:
    """Reduce (K, M) to a Craig-Bampton superelement.

    Parameters
    ----------
    K, M : sparse (n, n) symmetric stiffness and mass (SI units).
    boundary_dofs : indices of the master DOFs (kept physical, in this order).
    n_modes : number of fixed-interface modes (0 = Guyan).
    cutoff_hz : alternatively keep all fixed-interface modes below this frequency (Hz).
    max_modes : most fixed-interface modes to keep (``None``: no limit). With
        ``cutoff_hz``, at most ``max_modes + 1`` modes are ever computed: if the last is
        still below the cutoff the reduction stops with :class:`~cms.errors.ModeLimitError`
        instead of computing every interior mode (memory n_interior^2 in the worst case).
        ``n_modes`` above it is refused.
    residual_vectors : also keep the interior's static response to the inertia load of the
        constraint modes, K_ii^-1 (M_ii Psi + M_ib), made M-orthogonal to the kept modes
        (modal truncation augmentation, Dickens, Nakagawa & Wittbrodt 1997; Nastran's
        RESVEC). One block solve of n_boundary right-hand sides on the same
        factorization; it carries the quasi-static part of every truncated mode, so a
        lower cutoff reaches the same accuracy. They are appended to ``Phi`` after the
        eigenmodes, as Rayleigh-Ritz vectors of (K_ii, M_ii) in their own subspace, with
        their Ritz values in ``eigenvalues`` and their count in
        ``metadata["n_residual_vectors"]``.
    dof_names : names of all n DOFs, or of the boundary DOFs only (stored in the
        superelement as ``boundary_names``).
    node_coords / dof_layout / rigid_body_basis : rigid-body information (module doc).
    options : :class:`SolverOptions` (backend, threads, tolerance, ordering, eigen method).
    metadata : JSON-serialisable dict stored in the superelement.
    """

    def __init__(self, K, M, boundary_dofs, n_modes: int | None = None,
                 cutoff_hz: float | None = None, *, max_modes: int | None = None,
                 residual_vectors: bool = False,
                 dof_names=None, node_coords=None, dof_layout=None, rigid_body_basis=None,
                 options: SolverOptions = SolverOptions(), metadata: dict | None = None):
        self.K = sp.csr_matrix(K, dtype=float)
        self.M = sp.csr_matrix(M, dtype=float)
        n = self.K.shape[0]
        if self.K.shape != (n, n) or self.M.shape != (n, n):
            raise ReductionError("K and M must be square and of equal size", "shapes",
                                 (self.K.shape, self.M.shape))
        b = _checked_boundary(boundary_dofs, n)
        _check_mode_selection(n_modes, cutoff_hz, n - len(b), max_modes)
        if not isinstance(options, SolverOptions):
            raise ReductionError("options must be a cms.SolverOptions", "options", options)
        self.boundary_dofs = b
        mask = np.ones(n, dtype=bool)
        mask[b] = False
        self.interior_dofs = np.flatnonzero(mask)
        self.n_modes = n_modes
        self.cutoff_hz = cutoff_hz
        self.max_modes = max_modes
        self.dof_names = _full_dof_names(dof_names, b, n)
        self.points, self.kinds, self.R = _rigid_information(n, node_coords, dof_layout,
                                                             rigid_body_basis)
        self.options = options
        self.residual_vectors = bool(residual_vectors)
        self.metadata = dict(metadata or {})
        self.timings = Timings()
        self.superelement: Superelement | None = None
        self.factorization = None

    # ------------------------------------------------------------------
    def _length_scale(self) -> float:
        if self.points is not None:
            return float(np.ptp(self.points, axis=0).max()) or 1.0
        if self.R is not None:  # rotation columns carry lever arms (m)
            return float(np.abs(self.R[:, 3:]).max()) or 1.0
        return 1.0

    def _check_rigid_basis(self):
        R = self.R
        KR = self.K @ R
        knorm = abs(self.K).sum(axis=0).max()
        rel = np.linalg.norm(KR, axis=0) / (knorm * np.linalg.norm(R, axis=0))
        if rel.max() > RIGID_BASIS_TOL:
            j = int(np.argmax(rel))
            raise ReductionError("rigid-body vector is not a zero-energy motion of K "
                                 f"({rigid.MOTION_NAMES[j]}); wrong DOF layout or a "
                                 "grounded model?", "||K r||/(||K|| ||r||)", float(rel.max()))
        return rel

    def _check_mechanism(self):
        L = self._length_scale()
        free = rigid.free_rigid_motions(self.R, self.boundary_dofs, length_scale=L)
        if free.shape[1]:
            names = [rigid.describe_motion(free[:, j], L) for j in range(free.shape[1])]
            raise InteriorMechanismError(
                "boundary DOFs do not hold the component: K_ii is singular; free motion(s): "
                + "; ".join(names), motion="; ".join(names),
                components=free[:, 0] / np.linalg.norm(free[:, 0]))

    # ------------------------------------------------------------------
    def reduce(self) -> Superelement:
        t_all = time.perf_counter()
        b, i = self.boundary_dofs, self.interior_dofs
        K, M = self.K, self.M
        checks = {}
        if self.R is not None:
            checks["rigid_basis_residual"] = float(self._check_rigid_basis().max())
            self._check_mechanism()
        else:
            checks["rigid_body_checks"] = "skipped: no rigid-body information"
            log.warning("no rigid-body information (node_coords, dof_layout or rigid_body_basis): the "
                        "mechanism and mass checks are skipped; for a coupled component pass "
                        "rigid_body_basis=coupled.rigid_body_basis()")
        Kii = K[i][:, i].tocsc()
        Kib = K[i][:, b]
        Mii = M[i][:, i].tocsr()
        Mib = M[i][:, b]
        Kbb = K[b][:, b].toarray()
        Mbb = M[b][:, b].toarray()

        # one factorization serves constraint modes and eigen solve
        t0 = time.perf_counter()
        opt = self.options
        F = factor(Kii, backend=opt.backend, threads=opt.factor_threads, ordering=opt.ordering)
        F.threads = opt.threads       # solves (constraint modes, eigen) use ``threads``
        self.factorization = F
        self.timings.factorize = time.perf_counter() - t0

        t0 = time.perf_counter()
        Kib_d = Kib.toarray()
        Psi = -F.solve(Kib_d) if len(b) else np.zeros((len(i), 0))
        if len(b):
            r = np.linalg.norm(Kii @ Psi + Kib_d) / max(np.linalg.norm(Kib_d), 1e-300)
            checks["constraint_mode_residual"] = float(r)
            if not r <= CONSTRAINT_RESIDUAL_TOL:
                raise InteriorMechanismError("constraint-mode solve inaccurate: K_ii is (nearly) "
                                             f"singular (relative residual {r:.3e})",
                                             motion="unidentified (ill-conditioned K_ii)", pivot=r)
        self.timings.constraint_modes = time.perf_counter() - t0

        t0 = time.perf_counter()
        solves0, rhs0 = F.n_solves, F.n_rhs
        lam, Phi, res = self._modes(Kii, Mii, F)
        self.timings.eigen = time.perf_counter() - t0
        eigen_solves, eigen_rhs = F.n_solves - solves0, F.n_rhs - rhs0
        n_rv = 0
        if self.residual_vectors and len(b) and len(i) > Phi.shape[1]:
            t0 = time.perf_counter()
            G = F.solve(Mii @ Psi + Mib.toarray())
            W, theta = _augmentation(G, Phi, Kii, Mii)
            n_rv = W.shape[1]
            Phi = np.hstack([Phi, W])
            lam = np.concatenate([lam, theta])
            self.timings.eigen += time.perf_counter() - t0
        if len(res):
            checks["eigen_residual_max"] = float(res.max())

        t0 = time.perf_counter()
        with thread_limit(opt.threads):
            Kr, Mr = self._reduced_matrices(Kbb, Mbb, Kib_d, Mib, Kii, Mii, Psi, Phi)
        self.timings.assemble = time.perf_counter() - t0

        if self.R is not None:
            checks.update(self._rigid_checks(Kr, Mr))
        self.timings.total = time.perf_counter() - t_all
        meta = dict(self.metadata)
        meta.setdefault("mode_selection", {"n_modes": self.n_modes, "cutoff_hz": self.cutoff_hz})
        meta["solver"] = {"backend": F.backend, "threads": opt.threads, "tol": opt.tol,
                          "ordering": opt.ordering, "eigen_method": opt.eigen_method,
                          "eigen_solves": eigen_solves, "eigen_rhs": eigen_rhs}
        meta["n_residual_vectors"] = n_rv
        meta["timings_s"] = vars(self.timings).copy()
        meta["self_checks"] = checks
        names = ([self.dof_names[j] for j in b] if self.dof_names is not None
                 else [f"dof{j}" for j in b])
        pts = self.points[b] if self.points is not None else np.zeros((0, 3))
        kinds = self.kinds[b] if self.kinds is not None else np.full(len(b), -1)
        self.superelement = Superelement(
            K=Kr, M=Mr, Phi=Phi, Psi=Psi, boundary_dofs=b.copy(), interior_dofs=i.copy(),
            eigenvalues=lam, boundary_names=names, boundary_points=pts, boundary_kinds=kinds,
            metadata=meta)
        log.info("CB reduction n=%d boundary=%d modes=%d backend=%s: factor %.2f s, "
                 "constraint %.2f s, eigen %.2f s, total %.2f s", K.shape[0], len(b),
                 len(lam), F.backend, self.timings.factorize, self.timings.constraint_modes,
                 self.timings.eigen, self.timings.total)
        return self.superelement

    def reconstruct(self, q: np.ndarray) -> np.ndarray:
        """Full displacement field(s) from reduced coordinates (after ``reduce``)."""
        if self.superelement is None:
            raise ReductionError("call reduce() before reconstruct()", "superelement", None)
        return self.superelement.reconstruct(q)

    # ------------------------------------------------------------------
    def _modes(self, Kii, Mii, F):
        opt = self.options
        ni = Kii.shape[0]
        if self.n_modes == 0 or ni == 0:
            return np.zeros(0), np.zeros((ni, 0)), np.zeros(0)
        if self.n_modes is not None:
            r = lowest_modes(Kii, Mii, self.n_modes, factorization=F, tol=opt.tol,
                             threads=opt.threads, method=opt.eigen_method)
            self._check_positive(r.eigenvalues, Kii, Mii)
            return r.eigenvalues, r.vectors, r.residuals
        lam_cut = (2 * math.pi * self.cutoff_hz) ** 2
        # Batches of modes on the one factorization; each batch deflates the modes already
        # found (ARPACK only), so nothing is recomputed when the cutoff needs more modes.
        lams, vecs, ress = [], [], []
        limit = ni if self.max_modes is None else min(ni, self.max_modes + 1)
        k = min(limit, 12)
        while True:
            found = np.hstack(vecs) if vecs else None
            n_found = 0 if found is None else found.shape[1]
            k = min(k, limit - n_found)
            deflate = found if opt.eigen_method == "arpack" else None
            r = lowest_modes(Kii, Mii, k if deflate is not None else n_found + k, factorization=F,
                             tol=opt.tol, threads=opt.threads, method=opt.eigen_method, deflate=deflate)
            if deflate is None:  # block method: recompute from scratch, keep the new ones
                lams, vecs, ress = [], [], []
            self._check_positive(r.eigenvalues, Kii, Mii)
            lams.append(r.eigenvalues)
            vecs.append(r.vectors)
            ress.append(r.residuals)
            n_found = sum(len(x) for x in lams)
            if r.eigenvalues[-1] > lam_cut or n_found >= ni:
                lam, X, res = (np.concatenate(lams), np.hstack(vecs), np.concatenate(ress))
                o = np.argsort(lam)
                keep = o[lam[o] <= lam_cut]
                return lam[keep], X[:, keep], res[keep]
            if n_found >= limit:
                raise ModeLimitError(self.cutoff_hz, self.max_modes,
                                     math.sqrt(max(r.eigenvalues[-1], 0.0)) / (2 * math.pi))
            k = 2 * k

    @staticmethod
    def _check_positive(lam, Kii, Mii):
        # omega^2 must be clearly positive: a near-zero one is a non-rigid mechanism
        lam_ref = Kii.diagonal().sum() / Mii.diagonal().sum()
        if lam[0] <= 1e-10 * lam_ref:
            raise InteriorMechanismError("K_ii has a (near) zero-energy mode: omega^2 = "
                                         f"{lam[0]:.3e} (rad/s)^2", motion="unidentified "
                                         "non-rigid free motion (zero-frequency fixed-interface mode)",
                                         pivot=float(lam[0]))

    @staticmethod
    def _reduced_matrices(Kbb, Mbb, Kib, Mib, Kii, Mii, Psi, Phi):
        """Galerkin projection T^T K T, T^T M T of the CB basis T = [[I, 0], [Psi, Phi]].

        The modal blocks use explicit products (not the closed forms diag(omega^2)
        and zero coupling), so the reduced pencil is a Rayleigh-Ritz projection up
        to round-off even though Phi carries the eigen solver's residual.
        """
        nb, k = Psi.shape[1], Phi.shape[1]
        m = nb + k
        Kr = np.zeros((m, m))
        Mr = np.zeros((m, m))
        # stiffness: Psi^T (K_ib + K_ii Psi) is the constraint-mode residual (checked
        # <= CONSTRAINT_RESIDUAL_TOL), so the n_i * n_b^2 product Psi^T K_ii Psi is not formed
        Rc = Kib + Kii @ Psi
        Kbb_hat = Kbb + Kib.T @ Psi
        Kr[:nb, :nb] = Kbb_hat
        MPsi = Mii @ Psi
        MibPsi = Mib.T @ Psi
        Mr[:nb, :nb] = Psi.T @ MPsi + MibPsi + MibPsi.T + Mbb
        if k:
            Kbm = Rc.T @ Phi
            Kr[:nb, nb:] = Kbm
            Kr[nb:, :nb] = Kbm.T
            Kr[nb:, nb:] = Phi.T @ (Kii @ Phi)
            Mbm = Mib.T @ Phi + MPsi.T @ Phi
            Mr[:nb, nb:] = Mbm
            Mr[nb:, :nb] = Mbm.T
            Mr[nb:, nb:] = Phi.T @ (Mii @ Phi)
        return 0.5 * (Kr + Kr.T), 0.5 * (Mr + Mr.T)

    def _rigid_checks(self, Kr, Mr):
        """Rigid motion in reduced coordinates is q = [R_b; 0] (Psi R_b = R_i exactly)."""
        R = self.R
        Rr = np.zeros((Kr.shape[0], 6))
        Rr[:len(self.boundary_dofs)] = R[self.boundary_dofs]
        full = R.T @ (self.M @ R)
        red = Rr.T @ Mr @ Rr
        rel = np.abs(red - full).max() / np.abs(full).max()
        kr = np.linalg.norm(Kr @ Rr) / (np.abs(Kr).sum(axis=0).max() * np.linalg.norm(Rr))
        return {"rigid_mass_matrix_full": full.tolist(),
                "rigid_mass_matrix_rel_error": float(rel),
                "reduced_rigid_energy_residual": float(kr)}


def _checked_boundary(boundary_dofs, n: int) -> np.ndarray:
    """Boundary DOF indices as an int array: in range 0..n-1 and not repeated."""
    b = np.asarray(boundary_dofs, dtype=np.int64).ravel()
    if b.size and (b.min() < 0 or b.max() >= n):
        raise ReductionError("boundary DOF index out of range 0..n-1", "boundary_dofs",
                             int(b.min() if b.min() < 0 else b.max()))
    if len(np.unique(b)) != len(b):
        vals, counts = np.unique(b, return_counts=True)
        raise ReductionError("boundary DOFs repeated", "boundary_dofs",
                             vals[counts > 1].tolist())
    return b


def _check_mode_selection(n_modes, cutoff_hz, n_interior: int, max_modes) -> None:
    """Exactly one of ``n_modes`` (0..min(n_interior, max_modes)) or ``cutoff_hz``
    (finite, > 0 Hz); ``max_modes`` a non-negative integer or None."""
    if (n_modes is None) == (cutoff_hz is None):
        raise ReductionError("give exactly one of n_modes or cutoff_hz",
                             "(n_modes, cutoff_hz)", (n_modes, cutoff_hz))
    for name, v in (("n_modes", n_modes), ("max_modes", max_modes)):
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0):
            raise ReductionError(f"{name} must be an integer >= 0", name, v)
    if n_modes is not None and not n_modes <= n_interior:
        raise ReductionError(f"n_modes must be in 0..n_interior = {n_interior}", "n_modes", n_modes)
    if n_modes is not None and max_modes is not None and n_modes > max_modes:
        raise ReductionError(f"n_modes must be at most max_modes = {max_modes}", "n_modes", n_modes)
    if cutoff_hz is not None and not (isinstance(cutoff_hz, (int, float)) and 0 < cutoff_hz < math.inf):
        raise ReductionError("cutoff frequency must be a finite number > 0 (Hz)", "cutoff_hz",
                             cutoff_hz)


def _full_dof_names(dof_names, b: np.ndarray, n: int) -> list[str] | None:
    """Names of all n DOFs from names of all of them or of the boundary DOFs only
    (the others then named ``dof<j>``); ``None`` stays ``None``."""
    if dof_names is None:
        return None
    names = list(dof_names)
    if len(names) not in (n, len(b)):
        raise ReductionError("dof_names must name all n DOFs or the boundary DOFs",
                             "len(dof_names)", len(names))
    if len(names) == len(b) != n:
        full = [f"dof{j}" for j in range(n)]
        for j, name in zip(b, names):
            full[j] = name
        names = full
    return names


def _rigid_information(n: int, node_coords, dof_layout, rigid_body_basis):
    """(DOF points (n, 3) or None, DOF kinds (n,) or None, rigid-body basis (n, 6) or None)
    from whichever rigid-body information was given (module doc), in the order of
    precedence dof_layout, rigid_body_basis, node_coords."""
    if dof_layout is not None:
        pts, kinds = (np.asarray(a) for a in dof_layout)
        if pts.shape != (n, 3) or kinds.shape != (n,):
            raise ReductionError("dof_layout must be (points (n, 3), kinds (n,))",
                                 "dof_layout shapes", (pts.shape, kinds.shape))
        points, kinds = pts.astype(float), kinds.astype(int)
        return points, kinds, rigid.rigid_body_basis(points, kinds)
    if rigid_body_basis is not None:
        R = np.asarray(rigid_body_basis, dtype=float)
        if R.shape != (n, 6):
            raise ReductionError("rigid_body_basis must be (n, 6)", "rigid_body_basis.shape",
                                 R.shape)
        return None, None, R
    if node_coords is not None:
        X = np.asarray(node_coords, dtype=float).reshape(-1, 3)
        if 3 * len(X) != n:
            raise ReductionError("node_coords must have n/3 rows (3 DOFs per node)",
                                 "node_coords.shape", X.shape)
        points, kinds = rigid.solid_dof_layout(X)
        return points, kinds, rigid.rigid_body_basis(points, kinds)
    return None, None, None


def _augmentation(G, Phi, Kii, Mii, drop: float = 1e-6):
    """Residual vectors from the static responses ``G`` (n_i, n_b): M-orthogonal to the
    modes ``Phi`` and to each other, K-orthogonal among themselves (Rayleigh-Ritz in
    span(G) minus span(Phi)). Directions whose part outside span(Phi) is below ``drop``
    relative are dropped. Returns (W, theta) with W^T M W = I, W^T K W = diag(theta)."""
    MPhi = Mii @ Phi
    W = G / np.maximum(np.linalg.norm(G, axis=0), 1e-300)
    for _ in range(2):  # classical Gram-Schmidt twice against the modes
        W = W - Phi @ (MPhi.T @ W)
    MW = Mii @ W
    Gm = 0.5 * (W.T @ MW + MW.T @ W)
    s, Q = np.linalg.eigh(Gm)
    # drop relative to what the columns had before the projection (unit Euclidean norm
    # times the mass scale), so directions already inside span(Phi) go
    scale = max(float(Mii.diagonal().max()), 1e-300)
    keep = s > drop ** 2 * scale
    if not keep.any():
        return np.zeros((W.shape[0], 0)), np.zeros(0)
    W = W @ (Q[:, keep] / np.sqrt(s[keep]))
    W = W - Phi @ (MPhi.T @ W)   # re-project: the rotation can reintroduce round-off along Phi
    Kw = W.T @ (Kii @ W)
    Mw = W.T @ (Mii @ W)
    theta, Y = sla.eigh(0.5 * (Kw + Kw.T), 0.5 * (Mw + Mw.T))
    return W @ Y, theta


def guyan(K, M, boundary_dofs, **kw) -> Superelement:
    """Guyan (static) reduction = Craig-Bampton with no modes; ``kw`` are the reductor's
    keyword arguments (``dof_names``, ``node_coords``, ..., ``options``)."""
    return CraigBamptonReductor(K, M, boundary_dofs, n_modes=0, **kw).reduce()
