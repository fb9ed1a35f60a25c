"""Tests of the 4x4x4 Bernstein free-form deformation and its mirror symmetry."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.math3d.ffd import (
    FFD_NUM_HALF,
    FFD_NUM_POINTS,
    FreeFormDeformation,
    bernstein_basis,
    control_points,
    expand_half_ffd,
    ffd_deform,
    half_indices,
    mirror_ffd,
    symmetrize_ffd,
)

F64 = torch.float64
MIRROR = torch.tensor([1.0, 1.0, -1.0], dtype=F64)


def box_verts(*shape: int) -> torch.Tensor:
    return torch.rand(*shape, 3, dtype=F64) - 0.5


def test_phi_zero_is_exact_identity() -> None:
    verts = box_verts(3, 100)
    out = ffd_deform(verts, torch.zeros(3, FFD_NUM_POINTS, 3, dtype=F64))
    assert torch.equal(out, verts)
    verts32 = verts.float()
    assert torch.equal(ffd_deform(verts32, torch.zeros(3, 64, 3)), verts32)


def test_basis_partition_of_unity_and_nonnegative_in_box() -> None:
    basis = bernstein_basis(box_verts(2, 500))
    assert basis.shape == (2, 500, 64)
    torch.testing.assert_close(basis.sum(-1), torch.ones(2, 500, dtype=F64), atol=1e-14, rtol=0)
    assert bool((basis >= 0).all())


def test_basis_reproduces_linear_functions() -> None:
    # sum_ijk B_ijk(v) P_ijk = v and, for any affine f, sum B_ijk f(P_ijk) = f(v).
    verts = box_verts(400)
    basis = bernstein_basis(verts)
    lattice = control_points(F64)
    torch.testing.assert_close(basis @ lattice, verts, atol=1e-14, rtol=0)
    A = torch.randn(3, 3, dtype=F64)
    b = torch.randn(3, dtype=F64)
    torch.testing.assert_close(basis @ (lattice @ A.T + b), verts @ A.T + b, atol=1e-13, rtol=0)
    # Outside the box the polynomials extrapolate: weights still sum to one and reproduce v.
    outside = box_verts(50) * 1.6
    ob = bernstein_basis(outside)
    torch.testing.assert_close(ob.sum(-1), torch.ones(50, dtype=F64), atol=1e-13, rtol=0)
    torch.testing.assert_close(ob @ lattice, outside, atol=1e-13, rtol=0)


def test_flat_index_order_and_corner_interpolation() -> None:
    lattice = control_points(F64)
    assert lattice.shape == (64, 3)
    # Index i * 16 + j * 4 + k with i along x, j along y, k along z.
    expected_point = torch.tensor([1 / 3, 2 / 3, 1.0], dtype=F64) - 0.5
    torch.testing.assert_close(lattice[1 * 16 + 2 * 4 + 3], expected_point)
    # At a lattice corner only that control point has weight: moving it moves the corner.
    corner = torch.tensor([[0.5, -0.5, 0.5]], dtype=F64)  # (i, j, k) = (3, 0, 3)
    basis = bernstein_basis(corner)
    expected = torch.zeros(1, 64, dtype=F64)
    expected[0, 3 * 16 + 0 * 4 + 3] = 1.0
    torch.testing.assert_close(basis, expected)
    phi = torch.zeros(1, 64, 3, dtype=F64)
    phi[0, 51] = torch.tensor([0.1, 0.2, 0.3], dtype=F64)
    torch.testing.assert_close(ffd_deform(corner[None], phi)[0, 0], corner[0] + phi[0, 51])


def test_basis_matches_scalar_formula() -> None:
    v = torch.tensor([0.1, -0.3, 0.25], dtype=F64)
    u = (v + 0.5).tolist()

    def bern(n: int, t: float) -> float:
        return math.comb(3, n) * t**n * (1 - t) ** (3 - n)

    expected = torch.tensor(
        [bern(i, u[0]) * bern(j, u[1]) * bern(k, u[2]) for i in range(4) for j in range(4) for k in range(4)],
        dtype=F64,
    )
    torch.testing.assert_close(bernstein_basis(v[None])[0], expected, atol=1e-15, rtol=0)


def test_precomputed_basis_matches_and_broadcasts() -> None:
    verts = box_verts(60)
    phi = 0.1 * torch.randn(4, 64, 3, dtype=F64)
    batched = verts.expand(4, 60, 3)
    reference = ffd_deform(batched, phi)
    basis = bernstein_basis(verts)
    torch.testing.assert_close(ffd_deform(batched, phi, basis), reference)
    torch.testing.assert_close(ffd_deform(verts, phi, basis), reference)
    torch.testing.assert_close(ffd_deform(batched, phi, basis.expand(4, 60, 64)), reference)
    assert reference.shape == (4, 60, 3)


def test_symmetric_phi_preserves_mirror_symmetry() -> None:
    half = box_verts(2, 80)
    verts = torch.cat([half, half * MIRROR], dim=1)  # a z-mirror-symmetric vertex set
    phi = symmetrize_ffd(0.2 * torch.randn(2, 64, 3, dtype=F64))
    out = ffd_deform(verts, phi)
    # deform(v) mirrored == deform(mirror(v)), pointwise.
    torch.testing.assert_close(out[:, :80] * MIRROR, out[:, 80:], atol=1e-14, rtol=0)
    # A generic field breaks it (the test is not vacuous).
    generic = ffd_deform(verts, 0.2 * torch.randn(2, 64, 3, dtype=F64))
    assert (generic[:, :80] * MIRROR - generic[:, 80:]).abs().max().item() > 1e-3


def test_mirror_ffd_matches_mirrored_vertices() -> None:
    # For any phi: mirror(deform_phi(v)) == deform_{mirror(phi)}(mirror(v)).
    verts = box_verts(1, 50)
    phi = torch.randn(1, 64, 3, dtype=F64)
    lhs = ffd_deform(verts, phi) * MIRROR
    rhs = ffd_deform(verts * MIRROR, mirror_ffd(phi))
    torch.testing.assert_close(lhs, rhs, atol=1e-13, rtol=0)


def test_expand_half_and_symmetrize() -> None:
    phi_half = torch.randn(5, FFD_NUM_HALF, 3, dtype=F64)
    full = expand_half_ffd(phi_half)
    assert full.shape == (5, 64, 3)
    torch.testing.assert_close(mirror_ffd(full), full, atol=0, rtol=0)
    idx = half_indices()
    assert idx.shape == (32,) and idx.tolist() == sorted(idx.tolist())
    assert set((idx % 4).tolist()) == {0, 1}
    torch.testing.assert_close(full[:, idx], phi_half, atol=0, rtol=0)
    # Control point (i, j, k) mirrors to (i, j, 3 - k) with z negated.
    i, j, k = 2, 1, 0
    torch.testing.assert_close(full[:, i * 16 + j * 4 + 3 - k], full[:, i * 16 + j * 4 + k] * MIRROR)
    phi = torch.randn(5, 64, 3, dtype=F64)
    sym = symmetrize_ffd(phi)
    torch.testing.assert_close(symmetrize_ffd(sym), sym, atol=1e-15, rtol=0)
    torch.testing.assert_close(expand_half_ffd(sym[:, idx]), sym, atol=1e-15, rtol=0)
    # Projection: the residual is orthogonal to symmetric fields.
    assert abs(((phi - sym) * full).sum().item()) < 1e-10
    # The z displacement of a symmetric field is odd in k, so it sums to zero along each k row.
    z = sym[..., 2].reshape(5, 4, 4, 4)
    torch.testing.assert_close(z.sum(-1), torch.zeros(5, 4, 4, dtype=F64), atol=1e-14, rtol=0)


def test_gradcheck_phi_and_verts() -> None:
    verts = box_verts(2, 7).requires_grad_(True)
    phi = (0.1 * torch.randn(2, 64, 3, dtype=F64)).requires_grad_(True)
    assert torch.autograd.gradcheck(ffd_deform, (verts, phi))
    phi_half = (0.1 * torch.randn(2, 32, 3, dtype=F64)).requires_grad_(True)
    assert torch.autograd.gradcheck(lambda v, p: ffd_deform(v, expand_half_ffd(p)), (verts, phi_half))


def test_module_with_template_bank() -> None:
    templates = box_verts(3, 40)  # M = 3 templates with V = 40 vertices
    module = FreeFormDeformation(bernstein_basis(templates), half=True)
    assert "basis" in dict(module.named_buffers())
    ids = torch.tensor([2, 0, 2, 1])
    phi_half = 0.1 * torch.randn(4, 32, 3, dtype=F64)
    out = module(templates[ids], phi_half, ids)
    torch.testing.assert_close(out, ffd_deform(templates[ids], expand_half_ffd(phi_half)))
    full = FreeFormDeformation(bernstein_basis(templates[0]))
    torch.testing.assert_close(full(templates[:1].expand(2, 40, 3), torch.zeros(2, 64, 3, dtype=F64)),
                               templates[:1].expand(2, 40, 3))


def test_shape_errors() -> None:
    verts = box_verts(2, 10)
    with pytest.raises(ValueError, match="phi must have shape"):
        ffd_deform(verts, torch.zeros(2, 32, 3, dtype=F64))
    with pytest.raises(ValueError, match="basis batch"):
        ffd_deform(verts, torch.zeros(2, 64, 3, dtype=F64), bernstein_basis(box_verts(3, 10)))
    with pytest.raises(ValueError, match="basis must have shape"):
        ffd_deform(verts, torch.zeros(2, 64, 3, dtype=F64), bernstein_basis(box_verts(2, 9)))
    with pytest.raises(ValueError, match="phi_half"):
        expand_half_ffd(torch.zeros(2, 64, 3))
    with pytest.raises(ValueError, match="verts"):
        bernstein_basis(torch.zeros(10, 2))
