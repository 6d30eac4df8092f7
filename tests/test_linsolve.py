"""Linear solvers agree to their tolerance; AMG reuse and rebuild; true residuals."""

import numpy as np
import pytest
import scipy.sparse as sp

from capslide.fem.assembly import BulkForm, Dirichlet, rigid_body_modes
from capslide.fem.mesh import CapMeshSpec, cap_mesh
from capslide.fem.quality import poorly_shaped_dofs
from capslide.solvers.amg import PYAMG_DEFAULTS, SETTINGS
from capslide.solvers.linsolve import AMGSolver, DirectSolver, LinearSolveError, LUKrylovSolver, choose_linear_solver, make_solver

from fe_helpers import LAM, MU

# the fixture's 3,726 DOF fit in one coarse level at SETTINGS' max_coarse: force a hierarchy
MULTILEVEL = {**SETTINGS, "max_coarse": 50}


@pytest.fixture(scope="module")
def cap_system():
    return _cap_system(0.1)


def _cap_system(h0):
    mesh = cap_mesh(CapMeshSpec(R=47.1, H=10.0, h0=h0, band_half_width=8.0))
    form = BulkForm(mesh, LAM, MU)
    r, data = form.residual_and_tangent_data(np.zeros(mesh.n_dofs))
    bc = Dirichlet.on_nodes(mesh.base, form.pattern)
    bc.apply(data)
    A = form.pattern.matrix(data)
    rng = np.random.default_rng(0)
    b = rng.normal(size=mesh.n_dofs)
    b[bc.dofs] = 0.0
    return mesh, A, b, bc


def _unsymmetric(A, mesh, eps=0.3):
    """A plus an unsymmetric surface coupling like a sliding-friction tangent: dT_t/dg_n on (x, y) of each surface node."""
    nodes = mesh.surface_nodes[1:-1]
    diag = A.diagonal()
    C = sp.csr_matrix((eps * diag[2 * nodes], (2 * nodes, 2 * nodes + 1)), shape=A.shape)
    return (A + C).tocsr()


@pytest.mark.parametrize("kind", ["amg", "lu_krylov"])
@pytest.mark.parametrize("symmetric", [True, False])
def test_solvers_agree_with_direct(cap_system, kind, symmetric):
    mesh, A, b, bc = cap_system
    if not symmetric:
        A = _unsymmetric(A, mesh)
    x_ref, _ = DirectSolver().solve(A, b)
    solver = make_solver(kind, rtol=1e-10, near_null_space=rigid_body_modes(mesh.nodes))
    x, info = solver.solve(A, b)
    assert info.true_residual <= 1e-9
    assert np.linalg.norm(x - x_ref) <= 1e-7 * np.linalg.norm(x_ref)
    # two right-hand sides with the same matrix (the bordered system needs this)
    B = np.column_stack([b, np.roll(b, 7)])
    B[bc.dofs] = 0.0
    X, info2 = solver.solve(A, B)
    X_ref, _ = DirectSolver().solve(A, B)
    assert np.linalg.norm(X - X_ref) <= 1e-7 * np.linalg.norm(X_ref)
    assert not info2.rebuilt  # hierarchy / factorization reused


def test_rigid_body_modes_help_amg(cap_system):
    mesh, A, b, _ = cap_system
    with_rbm = AMGSolver(near_null_space=rigid_body_modes(mesh.nodes), symmetric=True, options=MULTILEVEL)
    plain = AMGSolver(near_null_space=None, symmetric=True, options=MULTILEVEL)
    it_rbm = with_rbm.solve(A, b)[1].iterations
    it_plain = plain.solve(A, b)[1].iterations
    assert it_rbm < it_plain


def test_amg_rebuild_rule(cap_system):
    """The hierarchy is rebuilt once the iterations beyond a fresh hierarchy's fewest add up to a setup's cost."""
    mesh, A, b, bc = cap_system
    solver = AMGSolver(near_null_space=rigid_body_modes(mesh.nodes), setup_cost=30.0, options=MULTILEVEL)
    _, info = solver.solve(A, b)
    fewest = info.iterations
    assert info.rebuilt and solver.stats["setups"] == 1 and solver._fewest_iterations == fewest
    _, info = solver.solve(A, b)
    assert not info.rebuilt and solver._excess_iterations == max(info.iterations - fewest, 0)
    # a much changed matrix: the stale hierarchy needs more iterations, and a rebuild follows once they add up
    A2 = (A + sp.diags(np.where(np.arange(A.shape[0]) % 7 == 0, 50.0, 0.0))).tocsr()
    stale = 0
    while True:
        _, info = solver.solve(A2, b)
        if info.rebuilt:
            break
        stale += 1
        assert info.iterations > fewest
    assert solver.stats["setups"] == 2 and stale >= 1
    solver.invalidate()
    assert solver._fewest_iterations is None
    _, info = solver.solve(A2, b)
    assert info.rebuilt


def test_a_hierarchy_built_on_a_hard_matrix_is_replaced():
    """A solve that rebuilds on a hard matrix (its first attempts failing) does not set the yardstick: the fewest
    iterations stay a good hierarchy's, and the next solves' excess soon rebuilds it (the sphere's spread stayed at
    90 CG iterations a solve for the rest of its path when the failed attempt set it)."""
    solver = AMGSolver(setup_cost=40.0)
    solver._ml = object()  # a hierarchy, as setup() leaves it
    solver._account(11.0, fresh=True, n_dofs=14_400)
    assert solver._ml is not None and solver._excess_iterations == 0.0
    solver._account(56.0, fresh=True, n_dofs=14_400)  # 500 + 500 on the old hierarchy, then 56 on a rebuilt one
    assert solver._fewest_iterations == 11.0 and solver._excess_iterations == 45.0 and solver._ml is None
    solver._ml, solver._excess_iterations = object(), 0.0  # as setup() leaves it
    solver._account(30.0, fresh=False, n_dofs=14_400)
    assert solver._ml is not None and solver._excess_iterations == 19.0
    solver._account(40.0, fresh=False, n_dofs=14_400)
    assert solver._ml is None  # 19 + 29 >= 40


def test_the_setup_cost_follows_the_measured_table():
    from capslide.solvers.amg import SETUP_COST_ITERATIONS, setup_cost_iterations

    for dofs, cost in SETUP_COST_ITERATIONS:
        assert setup_cost_iterations(dofs) == pytest.approx(cost)
    assert setup_cost_iterations(1_000) == 42.0 and setup_cost_iterations(10**7) == 86.0


def test_amg_restarts_from_its_iterate_before_rebuilding(cap_system):
    mesh, A, b, bc = cap_system
    needed = AMGSolver(near_null_space=rigid_body_modes(mesh.nodes), symmetric=True, options=MULTILEVEL).solve(A, b)[1].iterations
    # too few iterations for one pass, enough for two: the restart finishes the solve on the same hierarchy
    solver = AMGSolver(near_null_space=rigid_body_modes(mesh.nodes), symmetric=True, maxiter=int(0.7 * needed),
                       options=MULTILEVEL)
    solver.solve(A, b)  # first call builds the hierarchy (and restarts)
    x, info = solver.solve(A, b)
    assert not info.rebuilt and solver.stats["setups"] == 1
    assert info.iterations > solver.maxiter and info.true_residual <= 10 * solver.rtol
    # far too few iterations: restart, rebuild, then a clear error
    hopeless = AMGSolver(near_null_space=rigid_body_modes(mesh.nodes), symmetric=True, maxiter=2, options=MULTILEVEL)
    with pytest.raises(LinearSolveError, match="relative residual"):
        hopeless.solve(A, b)


def _amg_iterations(mesh, A, b, exact: bool, options: dict) -> int:
    dofs = poorly_shaped_dofs(mesh.nodes, mesh.cells) if exact else None
    solver = AMGSolver(near_null_space=rigid_body_modes(mesh.nodes), exact_dofs=dofs, options=options, symmetric=True)
    x, info = solver.solve(A, b)
    assert info.true_residual <= 10 * solver.rtol
    return info.iterations


def test_amg_iterations_stay_nearly_flat_under_refinement_of_the_graded_cap():
    """From 6.8k to 24k DOF (surface elements 0.05 to 0.0125 L0): CG iterations within 1.5x with SETTINGS and the
    exact solve on the poorly shaped cells' DOFs; more than 2x with pyamg's defaults. Without the exact solve,
    SETTINGS alone need over 1.5x the iterations at 24k DOF."""
    coarse, fine = _cap_system(0.05), _cap_system(0.0125)
    robust = [_amg_iterations(m, A, b, True, SETTINGS) for m, A, b, _ in (coarse, fine)]
    plain = [_amg_iterations(m, A, b, False, PYAMG_DEFAULTS) for m, A, b, _ in (coarse, fine)]
    assert robust[1] <= 1.5 * robust[0]
    assert plain[1] > 2 * plain[0]
    mesh, A, b, _ = fine
    assert _amg_iterations(mesh, A, b, False, SETTINGS) > 1.5 * robust[1]


def test_amg_repeats_bit_for_bit_whatever_the_global_random_state(cap_system):
    """pyamg draws from NumPy's global random state while it builds a hierarchy; with it seeded inside the setup, two
    runs solve alike (they differed by 6e-9 here, and a cap case's Krylov counts by up to 11 %), and the caller's
    random stream goes on as if the setup had not drawn from it."""
    mesh, A, b, _ = cap_system
    runs = []
    for seed in (1, 2):
        np.random.seed(seed)
        solver = AMGSolver(near_null_space=rigid_body_modes(mesh.nodes), symmetric=True, options=MULTILEVEL)
        x, info = solver.solve(A, b)
        runs.append((x, info.iterations, np.random.random()))
    assert len(solver._ml.levels) > 2
    np.testing.assert_array_equal(runs[0][0], runs[1][0])
    assert runs[0][1] == runs[1][1]
    np.random.seed(1)
    assert runs[0][2] == np.random.random()


def test_the_default_w_cycle_keeps_a_deep_hierarchy_as_good_as_a_two_level_one():
    """24k DOF (Q1): with SETTINGS the coarse level is solved exactly after one coarsening (13 CG iterations); a
    four-level hierarchy loses that with a V-cycle (20) and keeps it with the default W-cycle (13). On the graded
    cap meshes this is what keeps Q1 at 13-17 iterations from 12k to 1M DOF (V-cycle: 13-28)."""
    mesh, A, b, _ = _cap_system(0.0125)
    dofs = poorly_shaped_dofs(mesh.nodes, mesh.cells)

    def iterations(options, **kw):
        solver = AMGSolver(near_null_space=rigid_body_modes(mesh.nodes), exact_dofs=dofs, options=options,
                           symmetric=True, **kw)
        x, info = solver.solve(A, b)
        assert info.true_residual <= 10 * solver.rtol
        return info.iterations, len(solver._ml.levels)

    two_level, levels = iterations(SETTINGS)
    assert levels == 2
    (deep_v, levels), (deep_default, _) = iterations(MULTILEVEL, cycle="V"), iterations(MULTILEVEL)
    assert levels >= 4
    assert deep_v > 1.3 * two_level
    assert deep_default <= 1.1 * two_level


@pytest.mark.parametrize("symmetric", [True, False])
def test_amg_with_exact_block_agrees_with_direct(cap_system, symmetric):
    mesh, A, b, _ = cap_system
    if not symmetric:
        A = _unsymmetric(A, mesh)
    dofs = poorly_shaped_dofs(mesh.nodes, mesh.cells)
    assert 0 < len(dofs) < 0.15 * mesh.n_dofs
    solver = AMGSolver(near_null_space=rigid_body_modes(mesh.nodes), exact_dofs=dofs, options=MULTILEVEL, rtol=1e-10)
    x, info = solver.solve(A, b)
    x_ref, _ = DirectSolver().solve(A, b)
    assert info.iterations > 1 and info.true_residual <= 1e-9
    assert np.linalg.norm(x - x_ref) <= 1e-7 * np.linalg.norm(x_ref)


def test_lu_krylov_reuses_factorization(cap_system):
    mesh, A, b, bc = cap_system
    solver = LUKrylovSolver(rtol=1e-10)
    _, info = solver.solve(A, b)
    assert info.rebuilt and info.iterations <= 2
    A2 = (A * 1.0).tocsr()
    A2.data *= 1.0 + 0.01 * np.random.default_rng(2).uniform(size=A2.nnz)  # a nearby matrix
    x, info = solver.solve(A2, b)
    assert not info.rebuilt and info.true_residual <= 1e-9
    assert solver.stats["setups"] == 1


def test_unknown_solver():
    with pytest.raises(ValueError, match="allowed"):
        make_solver("magic")


def test_bordered_solve_matches_the_assembled_bordered_system(cap_system):
    """One GMRES run on [A c; d^T e] (stored LU of a nearby A as preconditioner) equals a direct solve of the
    assembled (n+1) system; the Schur-complement path of a solver without solve_bordered agrees."""
    from capslide.model.system import BorderedSolve

    mesh, A, b, bc = cap_system
    rng = np.random.default_rng(4)
    n = A.shape[0]
    c, d = rng.normal(size=n), rng.normal(size=n)
    c[bc.dofs] = d[bc.dofs] = 0.0
    e = 5.0 + abs(d @ c)
    rhs = np.concatenate([b, [0.3]])
    J = sp.bmat([[A, sp.csr_matrix(c[:, None])], [sp.csr_matrix(d[None, :]), sp.csr_matrix([[e]])]]).tocsc()
    exact = sp.linalg.spsolve(J, rhs)
    solver = LUKrylovSolver(rtol=1e-10)
    solver.solve(A, b)  # factorize A
    A2 = (A * 1.0).tocsr()
    A2.data *= 1.0 + 0.01 * rng.uniform(size=A2.nnz)
    J2 = sp.bmat([[A2, sp.csr_matrix(c[:, None])], [sp.csr_matrix(d[None, :]), sp.csr_matrix([[e]])]]).tocsc()
    exact2 = sp.linalg.spsolve(J2, rhs)
    x, info = solver.solve_bordered(A2, c, d, e, rhs)
    one = LUKrylovSolver(rtol=1e-10, max_iterations_before_refactor=100)
    one.solve(A, b)
    _, single = one.solve(A2, b)  # one right-hand side, same stored factors
    assert not info.rebuilt and 0 < info.iterations <= single.iterations + 3  # costs about one Krylov solve
    assert np.linalg.norm(x - exact2) <= 1e-8 * np.linalg.norm(exact2)
    assert np.linalg.norm(exact2 - exact) > 1e-4 * np.linalg.norm(exact)  # the nearby matrix is a different system
    two_solves = BorderedSolve(DirectSolver(), A2, c, d, e)(rhs)
    assert np.linalg.norm(two_solves - exact2) <= 1e-9 * np.linalg.norm(exact2)


@pytest.mark.parametrize(("kind", "n_dofs", "mixed", "expected"), [
    ("auto", 10, False, "lu_krylov"), ("auto", 11, False, "amg"), ("auto", 11, True, "lu_krylov"),
    ("amg", 5, False, "amg"), ("direct", 11, False, "direct"), ("lu_krylov", 11, False, "lu_krylov")])
def test_auto_takes_lu_up_to_the_dof_limit_and_amg_above_it(kind, n_dofs, mixed, expected):
    assert choose_linear_solver(kind, n_dofs, mixed, amg_above_dofs=10) == expected


class _CountingLU:
    """SuperLU factors that count their solves."""

    def __init__(self, A):
        self.lu, self.solves = sp.linalg.splu(A.tocsc()), 0

    def solve(self, b):
        self.solves += 1
        return self.lu.solve(b)


@pytest.mark.parametrize("fixed_height", [True, False])
def test_bordered_preconditioner_solves_for_its_border_once(cap_system, monkeypatch, fixed_height):
    """The preconditioner of solve_bordered is the exact inverse of [A0 c; d^T e]. A0^{-1} c costs one LU solve per
    factorization and array c, shared by the GMRES run and the next-increment estimate of a Newton iteration, and
    renewed after a refactorization. With d = 0 (a fixed height) it is solved only for a vector with a last entry."""
    from capslide.solvers import linsolve

    monkeypatch.setattr(linsolve, "_factor", lambda A, *_: _CountingLU(A))
    mesh, A, b, bc = cap_system
    rng = np.random.default_rng(7)
    n = A.shape[0]
    c, d = rng.normal(size=n), (np.zeros(n) if fixed_height else rng.normal(size=n))
    c[bc.dofs] = d[bc.dofs] = 0.0
    e = 1.0 if fixed_height else 5.0 + abs(d @ c)
    J = sp.bmat([[A, sp.csr_matrix(c[:, None])], [sp.csr_matrix(d[None, :]), sp.csr_matrix([[e]])]]).tocsc()
    solver = LUKrylovSolver(rtol=1e-10)
    solver.factor(A)
    expected = (0, 1) if fixed_height else (1, 0)  # the first call with a border entry (or d) solves for it
    for last, solves in zip((0.0, 0.7), expected):
        rhs = np.concatenate([b, [last]])
        exact = sp.linalg.spsolve(J, rhs)
        lu = solver._lu
        before = lu.solves
        x = solver.approximate_bordered(c, d, e, rhs)
        assert np.linalg.norm(x - exact) <= 1e-10 * np.linalg.norm(exact)
        border_solves = lu.solves - before - 1  # one solve applies the inverse
        assert border_solves == solves
    solver.solve_bordered(A, c, d, e, np.concatenate([b, [0.0 if fixed_height else 0.7]]))
    again = solver._lu.solves
    solver.approximate_bordered(c, d, e, np.concatenate([b, [0.7]]))
    assert solver._lu.solves == again + 1  # the border solve is kept for this c ...
    solver.approximate_bordered(c.copy(), d, e, np.concatenate([b, [0.7]]))
    assert solver._lu.solves == again + 3  # ... and made anew for another array
    solver.approximate_bordered(c, d, e, np.concatenate([b, [0.7]]))  # kept for c again
    A2 = (A * 1.0).tocsr()
    A2.data *= 1.0 + 0.01 * rng.uniform(size=A2.nnz)
    solver.factor(A2)
    J2 = sp.bmat([[A2, sp.csr_matrix(c[:, None])], [sp.csr_matrix(d[None, :]), sp.csr_matrix([[e]])]]).tocsc()
    rhs = np.concatenate([b, [0.7]])
    exact2 = sp.linalg.spsolve(J2, rhs)
    x = solver.approximate_bordered(c, d, e, rhs)  # new factors: the kept border solve must not serve them
    assert np.linalg.norm(x - exact2) <= 1e-10 * np.linalg.norm(exact2)


def test_gmres_applies_the_preconditioner_to_its_start_once(cap_system, monkeypatch):
    """SciPy's GMRES applies the preconditioner to the right-hand side twice when it starts from zero; the second
    application is answered from memory: a bordered solve takes one LU solve fewer, with the same result bit for
    bit."""
    from capslide.solvers import linsolve

    repeat_kept = linsolve._repeat_kept
    monkeypatch.setattr(linsolve, "_factor", lambda A, *_: _CountingLU(A))
    mesh, A, b, bc = cap_system
    rng = np.random.default_rng(9)
    n = A.shape[0]
    c, d = rng.normal(size=n), rng.normal(size=n)
    c[bc.dofs] = d[bc.dofs] = 0.0
    A2 = (A * 1.0).tocsr()
    A2.data *= 1.0 + 0.01 * rng.uniform(size=A2.nnz)

    def bordered_solve():
        solver = LUKrylovSolver(rtol=1e-8)
        solver.factor(A)
        x, info = solver.solve_bordered(A2, c, d, 5.0 + abs(d @ c), np.concatenate([b, [0.3]]))
        return x, info.iterations, solver._lu.solves

    x, iterations, solves = bordered_solve()
    monkeypatch.setattr(linsolve, "_repeat_kept", lambda apply: apply)
    x_every, iterations_every, solves_every = bordered_solve()
    np.testing.assert_array_equal(x, x_every)
    assert iterations == iterations_every >= 2 and solves == solves_every - 1
    calls = []
    kept = repeat_kept(lambda r: (calls.append(1), 2.0 * r)[1])
    r = rng.normal(size=5)
    first, again = kept(r), kept(r.copy())
    np.testing.assert_array_equal(first, again)
    assert len(calls) == 1
    first[:] = 0.0  # the caller may change what it was given
    np.testing.assert_array_equal(kept(r), 2.0 * r)
    np.testing.assert_array_equal(kept(r + 1.0), 2.0 * (r + 1.0))
    assert len(calls) == 2
