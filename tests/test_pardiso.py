"""MKL PARDISO factors (solver.factorization: pardiso): exact solves, the analysis kept per pattern, factors the same
bit for bit for the same matrix, and a clear refusal without MKL. Skipped where MKL is not installed."""

import numpy as np
import pytest
import scipy.sparse as sp

from capslide.config import ConfigError, apply_overrides, validate
from capslide.fem.assembly import BulkForm, Dirichlet
from capslide.fem.mesh import CapMeshSpec, cap_mesh
from capslide.model import cost
from capslide.model.build import build_model
from capslide.params import Parameters
from capslide.solvers import pardiso
from capslide.solvers.linsolve import DirectSolver, LUKrylovSolver, factorization_cost_in_solves, make_solver

from fe_helpers import LAM, MU

needs_mkl = pytest.mark.skipif(pardiso.mkl_runtime() is None, reason="MKL is not installed (pip install mkl)")


@pytest.fixture(scope="module")
def tangent():
    """A cap bulk tangent (base clamped) with an unsymmetric surface coupling like a friction tangent's, and a nearby
    matrix of the same pattern."""
    mesh = cap_mesh(CapMeshSpec(R=47.1, H=10.0, h0=0.1, band_half_width=8.0))
    form = BulkForm(mesh, LAM, MU)
    _, data = form.residual_and_tangent_data(np.zeros(mesh.n_dofs))
    Dirichlet.on_nodes(mesh.base, form.pattern).apply(data)
    A = form.pattern.matrix(data)
    nodes = mesh.surface_nodes[1:-1]
    coupling = sp.csr_matrix((0.3 * A.diagonal()[2 * nodes], (2 * nodes, 2 * nodes + 1)), shape=A.shape)
    A = (A + coupling).tocsr()
    A.sort_indices()
    B = A.copy()
    B.data = B.data * (1.0 + 0.05 * np.random.default_rng(1).uniform(size=B.nnz))
    return A, B


def residual(A, x, b):
    return np.linalg.norm(A @ x - b) / np.linalg.norm(b)


def exact(A, x, b) -> bool:
    """x solves A x = b to round-off: a relative residual within 10 times SuperLU's (1e-13 to 3e-12 here; the
    matrix's condition number is about 5e7)."""
    return residual(A, x, b) <= 10 * residual(A, sp.linalg.splu(A.tocsc()).solve(b), b)


@needs_mkl
def test_pardiso_solves_and_refactorizes_without_a_new_analysis(tangent, monkeypatch):
    A, B = tangent
    rng = np.random.default_rng(0)
    b, b2 = rng.normal(size=A.shape[0]), rng.normal(size=(A.shape[0], 3))
    phases = []
    call = pardiso.PardisoFactors._call
    monkeypatch.setattr(pardiso.PardisoFactors, "_call", lambda self, phase, *a: (phases.append(phase), call(self, phase, *a)))
    factors = pardiso.PardisoFactors(A)
    assert exact(A, factors.solve(b), b)
    X = factors.solve(b2)  # several right-hand sides at once
    assert X.shape == b2.shape and all(exact(A, X[:, j], b2[:, j]) for j in range(3))
    assert factors.fill > A.nnz
    factors.refactor(B)
    assert exact(B, factors.solve(b), b)
    assert residual(A, factors.solve(b), b) > 1e-3  # the factors are B's now
    assert phases == [11, 22, 33, 33, 22, 33, 33]  # one analysis; the refactorization is numeric only
    C = sp.eye(A.shape[0], format="csr") + A  # another pattern (the diagonal was already there: add an entry)
    C = (C + sp.csr_matrix(([1.0], ([0], [A.shape[0] - 1])), shape=A.shape)).tocsr()
    assert not factors.same_pattern(C)
    with pytest.raises(ValueError, match="pattern"):
        factors.refactor(C)


@needs_mkl
def test_pardiso_factors_of_the_same_matrix_are_the_same_bit_for_bit(tangent):
    """A refactorization gives the factors of a fresh analysis and factorization: a resumed run that refactorizes
    at a checkpoint repeats the uninterrupted one."""
    A, B = tangent
    b = np.random.default_rng(3).normal(size=A.shape[0])
    first = pardiso.PardisoFactors(B).solve(b)
    kept = pardiso.PardisoFactors(A)
    kept.refactor(B)
    np.testing.assert_array_equal(kept.solve(b), first)


@needs_mkl
def test_lu_krylov_with_pardiso_agrees_with_direct_and_keeps_one_analysis(tangent):
    A, B = tangent
    b = np.random.default_rng(5).normal(size=A.shape[0])
    solver = make_solver("lu_krylov", rtol=1e-10, factorization="pardiso")
    assert solver.factorization == "pardiso"
    x, info = solver.solve(A, b)
    exact, _ = DirectSolver().solve(A, b)
    assert info.rebuilt and np.linalg.norm(x - exact) <= 1e-9 * np.linalg.norm(exact)
    handle = solver._pardiso
    solver.invalidate()  # as a checkpoint save does
    x, info = solver.solve(B, b)
    assert info.rebuilt and solver._pardiso is handle  # refactorized in place, the analysis kept
    assert np.linalg.norm(B @ x - b) <= 1e-9 * np.linalg.norm(b)
    assert isinstance(make_solver("lu_krylov"), LUKrylovSolver) and make_solver("lu_krylov").factorization == "superlu"


def test_pardiso_without_mkl_is_refused_in_one_line(paper_config, monkeypatch):
    monkeypatch.setattr(cost, "mkl_runtime", lambda: None)
    params = Parameters.from_config(validate(apply_overrides(paper_config, ["solver.factorization=pardiso"])))
    with pytest.raises(ConfigError) as err:
        cost.check_factorization(params)
    message = str(err.value)
    assert "solver.factorization = 'pardiso'" in message and "pip install mkl" in message and "\n" not in message
    with pytest.raises(ConfigError):
        build_model(params)
    with pytest.raises(ConfigError, match="solver.factorization"):
        validate(apply_overrides(paper_config, ["solver.factorization=umfpack"]))


@needs_mkl
def test_a_case_with_pardiso_resumes_bit_for_bit_and_agrees_with_superlu(paper_config, tmp_path):
    """A coarse case with solver.factorization pardiso, killed and resumed from its checkpoint, repeats the
    uninterrupted run; its QoIs agree with SuperLU's to the Newton tolerance."""
    from test_checkpoint import COARSE, Killed, assert_same_history, kill_after_steps, run_saving

    from capslide.io.checkpoint import config_text, load_checkpoint

    config = validate(apply_overrides(paper_config, [*COARSE, "solver.factorization=pardiso"]))
    params = Parameters.from_config(config)
    full = run_saving(params, tmp_path / "full", 7)
    with pytest.raises(Killed):
        run_saving(params, tmp_path / "ckpt", 7, observers=[kill_after_steps(40)])
    resumed = run_saving(params, tmp_path / "ckpt", 7, resume=load_checkpoint(tmp_path / "ckpt", config_text(config)))
    assert_same_history(full, resumed)
    superlu = run_saving(Parameters.from_config(validate(apply_overrides(paper_config, COARSE))), tmp_path / "slu", 7)
    assert full.status == superlu.status
    for name in full.scalars:
        assert full.scalars[name] == pytest.approx(superlu.scalars[name], rel=1e-6, abs=1e-9), name


def block_grid_3d(n: int) -> sp.csr_matrix:
    """A 27-point stencil on an n^3 grid with dense 3x3 node blocks (random, diagonally dominant): its LU factors
    fill in as a 3D hexahedral tangent's do."""
    line = sp.diags([1.0, 1.0, 1.0], [-1, 0, 1], shape=(n, n))
    A = sp.kron(sp.kron(sp.kron(line, line), line), np.ones((3, 3))).tocsr()
    A.data = np.random.default_rng(0).standard_normal(A.nnz)
    A = (A + 30.0 * sp.eye(A.shape[0])).tocsr()
    A.sort_indices()
    return A


@needs_mkl
def test_factors_that_fill_in_are_kept_until_their_cost_in_solves_is_spent(tangent):
    """A refactorization is worth as many Krylov iterations as it costs solves: about 10 on a 2D tangent (the
    floor of 15 holds), tens on 3D factors, where PARDISO's counted flops and fill set it. On a drifting sequence
    of bordered systems the 3D factors are then renewed less often than at the floor (SuperLU's rule)."""
    assert factorization_cost_in_solves(pardiso.PardisoFactors(tangent[0])) < 15
    A = block_grid_3d(12)
    assert 25 < factorization_cost_in_solves(pardiso.PardisoFactors(A)) < 40
    n, rng = A.shape[0], np.random.default_rng(2)
    drift, c, d, b = rng.uniform(-1, 1, A.nnz), rng.normal(size=n), rng.normal(size=n), rng.normal(size=n + 1)
    setups = {}
    for kind in ("superlu", "pardiso"):
        solver = make_solver("lu_krylov", factorization=kind)
        for k in range(40):
            B = A.copy()
            B.data = A.data * (1.0 + 0.003 * k * drift)
            solver.solve_bordered(B, c, d, 50.0, b)
        setups[kind] = solver.stats["setups"]
    assert setups == {"superlu": 6, "pardiso": 4}


@needs_mkl
def test_single_precision_factors_precondition_gmres_to_the_double_answer(tangent, paper_config):
    """solver.factor_precision single: PARDISO factors and solves in float32 (one solve leaves a relative residual
    of 6e-4 on this tangent, 1e-5 on the experiment scene's, where double leaves round-off), and GMRES, in double,
    still reaches the tolerance and the direct answer, in more iterations. The same matrix gives the same factors bit
    for bit, as in double."""
    A, B = tangent
    b = np.random.default_rng(7).normal(size=A.shape[0])
    single = pardiso.PardisoFactors(A, single=True)
    one_solve = single.solve(b)
    assert one_solve.dtype == np.float64 and single.solve(np.stack([b, b], axis=1)).shape == (A.shape[0], 2)
    assert 1e-9 < residual(A, one_solve, b) < 1e-2 and residual(A, pardiso.PardisoFactors(A).solve(b), b) < 1e-11
    again = pardiso.PardisoFactors(B, single=True)
    again.refactor(A)
    np.testing.assert_array_equal(again.solve(b), one_solve)
    near = A.copy()  # a matrix 0.1 % away, as the next Newton iterate's tangent
    near.data = A.data * (1.0 + 1e-3 * np.random.default_rng(8).uniform(size=A.nnz))
    exact_x, _ = DirectSolver().solve(near, b)
    its = {}
    for precision in ("double", "single"):
        solver = make_solver("lu_krylov", rtol=1e-10, factorization="pardiso", single=precision == "single")
        solver.solve(A, b)  # the factors of A precondition the solve with the nearby matrix
        x, info = solver.solve(near, b)
        assert not info.rebuilt and np.linalg.norm(x - exact_x) <= 1e-8 * np.linalg.norm(exact_x), precision
        its[precision] = info.iterations
    assert its["double"] < its["single"], its  # 13 and 31 on this 2D tangent (condition number about 5e7)
    params = Parameters.from_config(validate(apply_overrides(paper_config, ["solver.factorization=pardiso",
                                                                            "solver.factor_precision=single"])))
    assert build_model(params).solver.single
    with pytest.raises(ConfigError, match="solver.factor_precision = 'single' is not allowed with "
                                          "solver.factorization = superlu"):
        validate(apply_overrides(paper_config, ["solver.factor_precision=single"]))
