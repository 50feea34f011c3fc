r"""Exact shear-torsion domain of a joint under Coulomb friction: support function, closest-point
return and tangent (numba).

A joint whose points carry the friction capacity ``tau(y) = max(c - mu sigma(y), 0)`` [Pa]
(``sigma`` the capped normal stress of :mod:`dem.kernels.contact_stress`, tension positive)
admits the shear and torsion ``s = (V1, V2, M3')`` [N, N m] of every traction field with
``|t(y)| <= tau(y)``; ``M3'`` is taken about a reference point (the origin of the region
coordinates). That set ``K`` is convex; its support function for a rigid slip
``w = (w1, w2, omega)`` (slip of the reference point [m], twist [rad]) is

.. math:: h(w) = \int \tau(y)\,|v(y)|\,dA,\qquad v(y) = (w_1 - \omega y_2,\ w_2 + \omega y_1),

and its support point, a boundary point of ``K`` with outward normal ``w``, is
``g = grad h = int tau (u, y1 u2 - y2 u1) dA`` with ``u = v / |v|``: every point slides along
its own slip. The Hessian is ``H = int tau / |v| z z^T dA``, ``z = (-u2, u1, y . u)``; ``H w = 0``.
The fibre law's grid of springs (:mod:`dem.kernels.fibre_law`) has the same domain with the
integral replaced by its sum, so this is its limit on an infinitely fine grid; under uniform
pressure on a rectangle, the pure torsion ``h(0, 0, 1) = mu N c_T`` with ``c_T`` the mean
distance of the rectangle's points to its centre.

The integrals are taken over the parts of the joint where ``tau`` is linear (cut by the lines
``sigma = -f_c`` and ``sigma = min(sigma_t, c / mu)``), exactly in the radial variable: each
part is a fan of triangles from the rotation centre ``c = (-w2, w1) / omega``, where ``|v|``
has its cone point. In collapsed coordinates ``y = c + t (a - c + s (b - a))`` the integrands
are cubic in ``t`` (two Gauss points are exact) and smooth in ``s`` except near the foot of the
centre on the edge line, which a ``sinh`` substitution resolves (Johnston & Elliott's
transformation for nearly singular integrals). A centre further than ``FAR`` radii from a part
leaves the integrands smooth there; the fan is then taken from the part's vertex mean.

The return of a trial ``s_t`` outside ``K`` is its nearest point in the elastic energy
``(s - s_t)^T C^{-1} (s - s_t)``, ``C = diag(k_t A, k_t A, k_t J_p)``: the flow is normal to
``K``, so the plastic slip and twist are ``w`` with ``C w + g(w) = s_t`` (the return of a rigid
contact under Coulomb friction at a fixed pressure). That is the minimum of the convex
``Phi(w) = w^T C w / 2 + h(w) - s_t . w``; ``w = 0`` (inside) exactly when
``rho(d) = (s_t . d - h(d)) / |d|_C <= 0`` for every direction ``d``. :func:`project` first
maximises ``rho`` over directions (Newton on the sphere ``|d|_C = 1``, from ``d = C^{-1} s_t``,
which has ``s_t . d > 0``, as every outward direction of a trial outside has): a direction with
``rho > 0`` proves the trial outside and starts Newton on ``Phi`` from its best point
``w = rho d``; a maximum below ``-band h`` keeps the trial elastic; in between (a trial on the
boundary to within ``band``) the action is the trial with the tangent of continued flow.
"""

import math

import numpy as np
from numba import njit

from dem.kernels.contact_stress import MAX_VERTICES, clip_half_plane, origin_moments

MAX_REGION = MAX_VERTICES + 3  # corners of a part after the two cuts (and a spare)
FAR = 8.0  # rotation centres further than FAR part radii leave the integrands smooth
Z_SPAN = 1.5  # longest sub-interval of the sinh variable per Gauss rule
THIN = 1e-11  # fan triangles thinner than this fraction of the part radius are skipped
ASCENT_ITERATIONS = 60
NEWTON_ITERATIONS = 60
N_ACC = 22  # accumulators: h, g (3), H (3 x 3), G (3 x 3)

# Gauss-Legendre rules on [0, 1]: 6 points (smooth integrands), 2 points (cubic in t)
_X6, _W6 = np.polynomial.legendre.leggauss(6)
GAUSS6_X = 0.5 * (_X6 + 1.0)
GAUSS6_W = 0.5 * _W6
GAUSS2_X = np.array([0.5 - 0.5 / math.sqrt(3.0), 0.5 + 0.5 / math.sqrt(3.0)])
GAUSS2_W = np.array([0.5, 0.5])


@njit(cache=True)
def capacity_regions(poly, n, sigma, strength, friction, centre, out_regions, out_beta):
    """The parts of a joint where its friction capacity is linear, about ``centre``.

    Parameters
    ----------
    poly : (>= n, 2) float64
        Joint corners ``(y1, y2)`` about its centroid, CCW [m].
    n : int
        Corners.
    sigma : (3,) float64
        Trial normal stress ``sigma(y) = sigma[0] + sigma[1] y1 + sigma[2] y2`` [Pa, Pa/m].
    strength : (2,) float64
        ``(sigma_t, f_c)``: tensile and compressive strength [Pa] (``f_c = inf``: none).
    friction : (2,) float64
        ``(c, mu)``: cohesion [Pa] and friction coefficient [-].
    centre : (2,) float64
        Reference point of the torsion, about the centroid [m].
    out_regions : (3, MAX_REGION, 2) float64
        Corners of the parts about ``centre``: 0 the linear part, 1 the crushed part
        (``sigma <= -f_c``), 2 the part above ``min(sigma_t, c / mu)``.
    out_beta : (3, 3) float64
        Capacity ``tau = beta0 + beta1 y1 + beta2 y2`` [Pa, Pa/m] on each part (about
        ``centre``).

    Returns
    -------
    counts : (3,) int64
        Corners of each part (< 3: empty).
    """
    a, b1, b2 = sigma[0], sigma[1], sigma[2]
    sigma_t, f_c = strength[0], strength[1]
    c, mu = friction[0], friction[1]
    top = min(sigma_t, c / mu) if mu > 0.0 else sigma_t
    counts = np.zeros(3, dtype=np.int64)
    scratch = np.empty((n + 2, 2))
    part = np.empty((n + 2, 2))
    m = clip_half_plane(poly, n, np.array((top - a, -b1, -b2)), scratch)
    if math.isfinite(f_c):
        m = clip_half_plane(scratch, m, np.array((a + f_c, b1, b2)), part)
    else:
        part[:m] = scratch[:m]
    _store(part, m, centre, 0, out_regions, counts)
    # tau = c - mu sigma, about the centre
    out_beta[0, 0] = c - mu * (a + b1 * centre[0] + b2 * centre[1])
    out_beta[0, 1], out_beta[0, 2] = -mu * b1, -mu * b2
    if math.isfinite(f_c):
        m = clip_half_plane(poly, n, np.array((-f_c - a, -b1, -b2)), part)
        _store(part, m, centre, 1, out_regions, counts)
        out_beta[1, 0], out_beta[1, 1], out_beta[1, 2] = c + mu * f_c, 0.0, 0.0
    tau_top = max(c - mu * sigma_t, 0.0)
    if tau_top > 0.0:
        m = clip_half_plane(poly, n, np.array((a - top, b1, b2)), part)
        _store(part, m, centre, 2, out_regions, counts)
        out_beta[2, 0], out_beta[2, 1], out_beta[2, 2] = tau_top, 0.0, 0.0
    return counts


@njit(cache=True)
def _store(part, m, centre, k, out_regions, counts):
    for i in range(m):
        out_regions[k, i, 0] = part[i, 0] - centre[0]
        out_regions[k, i, 1] = part[i, 1] - centre[1]
    counts[k] = m


@njit(cache=True)
def support(w, regions, counts, beta, acc):
    """``h(w)``, ``g(w)``, ``H(w)`` and ``G = d g / d beta`` of part 0 into ``acc`` (N_ACC,):
    ``acc[0] = h``, ``acc[1:4] = g``, ``acc[4:13] = H`` (row-major), ``acc[13:22] = G``
    (row-major, columns ``beta0, beta1, beta2``). ``w`` (3,) must not be 0."""
    for i in range(N_ACC):
        acc[i] = 0.0
    for k in range(3):
        if counts[k] >= 3:
            _integrate_part(regions[k], counts[k], beta[k], k == 0, w, acc)


@njit(cache=True)
def _integrate_part(poly, n, beta, is_linear, w, acc):
    """Add the integrals over the CCW polygon ``poly[:n]`` (module notes)."""
    m1, m2 = 0.0, 0.0
    for j in range(n):
        m1 += poly[j, 0] / n
        m2 += poly[j, 1] / n
    radius = 0.0
    for j in range(n):
        radius = max(radius, math.hypot(poly[j, 0] - m1, poly[j, 1] - m2))
    near = False
    if w[2] != 0.0:
        c1, c2 = -w[1] / w[2], w[0] / w[2]
        near = math.hypot(c1 - m1, c2 - m2) <= FAR * radius
    if near:
        apex = np.array((c1, c2))
    else:
        apex = np.array((m1, m2))
    for j in range(n):
        a = poly[j]
        b = poly[(j + 1) % n]
        e1, e2 = a[0] - apex[0], a[1] - apex[1]
        l1, l2 = b[0] - a[0], b[1] - a[1]
        length = math.hypot(l1, l2)
        if length == 0.0:
            continue
        twice_area = e1 * l2 - e2 * l1  # signed: a centre outside the part cancels
        if abs(twice_area) <= THIN * radius * length:
            continue
        if near:
            _fan_singular(apex, e1, e2, l1, l2, length, twice_area, beta, is_linear, w, acc)
        else:
            for i in range(GAUSS6_X.size):
                s = GAUSS6_X[i]
                for k in range(GAUSS6_X.size):
                    t = GAUSS6_X[k]
                    y1 = apex[0] + t * (e1 + s * l1)
                    y2 = apex[1] + t * (e2 + s * l2)
                    weight = twice_area * t * GAUSS6_W[i] * GAUSS6_W[k]
                    _add_point(y1, y2, weight, beta, is_linear, w, acc)


@njit(cache=True)
def _fan_singular(apex, e1, e2, l1, l2, length, twice_area, beta, is_linear, w, acc):
    """Triangle ``(apex, a, b)`` with ``|v| = 0`` at the apex; ``e = a - apex``, ``l = b - a``:
    two Gauss points in ``t``, the ``sinh`` rule in ``s`` about the foot of the apex."""
    foot = -(e1 * l1 + e2 * l2) / (length * length)
    scale = abs(twice_area) / (length * length)  # distance to the edge line / length
    cuts = np.array((0.0, foot, 1.0)) if 0.0 < foot < 1.0 else np.array((0.0, 1.0, 1.0))
    for p in range(2):
        lo, hi = cuts[p], cuts[p + 1]
        if hi <= lo:
            continue
        z0 = math.asinh((lo - foot) / scale)
        z1 = math.asinh((hi - foot) / scale)
        pieces = max(1, int(math.ceil((z1 - z0) / Z_SPAN)))
        dz = (z1 - z0) / pieces
        for q in range(pieces):
            for i in range(GAUSS6_X.size):
                z = z0 + dz * (q + GAUSS6_X[i])
                s = foot + scale * math.sinh(z)
                ds = scale * math.cosh(z) * dz * GAUSS6_W[i]
                r1, r2 = e1 + s * l1, e2 + s * l2
                for k in range(2):
                    t = GAUSS2_X[k]
                    weight = twice_area * t * ds * GAUSS2_W[k]
                    _add_point(apex[0] + t * r1, apex[1] + t * r2, weight, beta, is_linear, w, acc)


@njit(cache=True)
def _add_point(y1, y2, weight, beta, is_linear, w, acc):
    v1 = w[0] - w[2] * y2
    v2 = w[1] + w[2] * y1
    r = math.hypot(v1, v2)
    if r == 0.0:
        return
    tau = beta[0] + beta[1] * y1 + beta[2] * y2
    u1, u2 = v1 / r, v2 / r
    e = (u1, u2, y1 * u2 - y2 * u1)
    z = (-u2, u1, y1 * u1 + y2 * u2)
    wt = weight * tau
    acc[0] += wt * r
    for i in range(3):
        acc[1 + i] += wt * e[i]
        for j in range(3):
            acc[4 + 3 * i + j] += wt / r * z[i] * z[j]
    if is_linear:
        basis = (1.0, y1, y2)
        for i in range(3):
            for j in range(3):
                acc[13 + 3 * i + j] += weight * e[i] * basis[j]


@njit(cache=True)
def _tangent_basis(d, C):
    """Two vectors spanning ``{x: x . C d = 0}``, orthonormal in the ``C`` inner product."""
    basis = np.zeros((2, 3))
    count = 0
    for axis in range(3):
        x = np.zeros(3)
        x[axis] = 1.0
        x -= (x @ (C * d)) * d
        for k in range(count):
            x -= (x @ (C * basis[k])) * basis[k]
        norm = math.sqrt(x @ (C * x))
        if norm > 1e-6 and count < 2:
            basis[count] = x / norm
            count += 1
    return basis


@njit(cache=True)
def _ascent_step(sigma_t, C, d, psi, acc):
    """Newton step (a gradient step where the reduced Hessian is not negative) for the
    maximum of ``rho`` on the sphere ``|d|_C = 1``; returns ``(step (3,), |reduced gradient|)``."""
    g = acc[1:4]
    H = acc[4:13].reshape((3, 3))
    r = sigma_t - g
    cd = C * d
    grad = r - psi * cd
    hess = -H - np.outer(r, cd) - np.outer(cd, r) - psi * np.diag(C) + 3.0 * psi * np.outer(cd, cd)
    basis = _tangent_basis(d, C)
    g2 = basis @ grad
    h2 = basis @ hess @ basis.T
    det = h2[0, 0] * h2[1, 1] - h2[0, 1] * h2[1, 0]
    if h2[0, 0] < 0.0 and det > 0.0:
        alpha = -np.linalg.solve(h2, g2)
    else:
        alpha = g2 / (abs(h2[0, 0]) + abs(h2[1, 1]) + math.hypot(g2[0], g2[1]) + 1e-300)
    norm = math.hypot(alpha[0], alpha[1])
    if norm > 0.5:  # at most about half a radian on the sphere
        alpha *= 0.5 / norm
    return alpha @ basis, math.hypot(g2[0], g2[1])


@njit(cache=True)
def _unit(d, C):
    return d / math.sqrt(d @ (C * d))


@njit(cache=True)
def _max_direction(sigma_t, C, regions, counts, beta, band, acc):
    """The direction of largest ``rho`` (module notes), stopped at the first with
    ``rho > -band h``, or where the gradient on the sphere is below ``1e-3 |rho|`` (the
    Newton step would then raise ``rho`` by a negligible part of the way to 0). Returns
    ``(d, rho)``; ``acc`` holds the support terms at ``d``."""
    d = _unit(sigma_t / C, C)
    support(d, regions, counts, beta, acc)
    psi = sigma_t @ d - acc[0]
    scale = math.sqrt(sigma_t @ (sigma_t / C)) + acc[0]
    trial = np.empty(N_ACC)
    for _ in range(ASCENT_ITERATIONS):
        if psi > -band * acc[0]:
            break
        step, size = _ascent_step(sigma_t, C, d, psi, acc)
        if size <= 1e-3 * abs(psi) or size <= 1e-15 * scale:
            break
        moved = False
        for _ in range(30):
            new = _unit(d + step, C)
            support(new, regions, counts, beta, trial)
            new_psi = sigma_t @ new - trial[0]
            if new_psi > psi:
                d, psi, moved = new, new_psi, True
                acc[:] = trial
                break
            step *= 0.5
        if not moved:
            break
    return d, psi


@njit(cache=True)
def solve_stiffness(A, b):
    """``A^{-1} b`` for the (3, 3) matrix ``A = diag(C) + H`` (``H`` the support function's
    Hessian, positive semidefinite in exact arithmetic) and ``b`` (3,) or (3, k); where
    round-off makes ``A`` exactly singular, the least-squares solution of least norm. The law
    runs inside numba's parallel loops, which cannot carry the exception LAPACK's solve would
    raise there."""
    if np.linalg.det(A) != 0.0:
        return np.linalg.solve(A, b)
    return np.linalg.pinv(A) @ b


@njit(cache=True)
def _minimise(sigma_t, C, w, regions, counts, beta, acc):
    """Newton with backtracking on ``Phi(w)`` from a ``w`` with ``Phi < 0``; returns the
    minimiser, ``acc`` the support terms there."""
    support(w, regions, counts, beta, acc)
    phi = 0.5 * w @ (C * w) + acc[0] - sigma_t @ w
    scale = math.sqrt(sigma_t @ (sigma_t / C))
    trial = np.empty(N_ACC)
    res = C * w + acc[1:4] - sigma_t
    size = math.sqrt(res @ (res / C))
    for _ in range(NEWTON_ITERATIONS):
        if size <= 1e-13 * scale:
            break
        step = -solve_stiffness(np.diag(C) + acc[4:13].reshape((3, 3)), res)
        slope = res @ step
        length = 1.0
        moved = False
        for _ in range(40):
            new = w + length * step
            support(new, regions, counts, beta, trial)
            new_phi = 0.5 * new @ (C * new) + trial[0] - sigma_t @ new
            new_res = C * new + trial[1:4] - sigma_t
            new_size = math.sqrt(new_res @ (new_res / C))
            # sufficient decrease of Phi, or (where Phi's change is below its round-off, near
            # the minimum) of the residual
            if new_phi <= phi + 1e-4 * length * slope or new_size <= 0.5 * size:
                w, phi, res, size, moved = new, new_phi, new_res, new_size, True
                acc[:] = trial
                break
            length *= 0.5
        if not moved:
            break
    return w


@njit(cache=True)
def capacity_centroid(regions, counts, beta):
    """``(V_u, y1, y2)``: the total capacity ``int tau dA`` [N] and its centroid about the
    reference point [m] (0 where the capacity is 0)."""
    total, first1, first2 = 0.0, 0.0, 0.0
    moments = np.empty(6)
    for k in range(3):
        if counts[k] < 3:
            continue
        moments[:] = 0.0
        origin_moments(regions[k], counts[k], 1.0, moments)
        b = beta[k]
        total += b[0] * moments[0] + b[1] * moments[1] + b[2] * moments[2]
        first1 += b[0] * moments[1] + b[1] * moments[3] + b[2] * moments[4]
        first2 += b[0] * moments[2] + b[1] * moments[4] + b[2] * moments[5]
    if total <= 0.0:
        return 0.0, 0.0, 0.0
    return total, first1 / total, first2 / total


@njit(cache=True)
def polar_capacity(regions, counts, beta, c1, c2):
    """``(J, r)``: ``int tau |y - c|^2 dA`` [N m] and the largest distance of a corner of the
    capacity's parts from ``c = (c1, c2)`` [m] (fans of triangles, each integrated by the
    4-point rule exact for cubics)."""
    bary = ((1.0 / 3.0, 1.0 / 3.0), (0.6, 0.2), (0.2, 0.6), (0.2, 0.2))
    weights = (-27.0 / 48.0, 25.0 / 48.0, 25.0 / 48.0, 25.0 / 48.0)
    polar, reach = 0.0, 0.0
    for k in range(3):
        n = counts[k]
        if n < 3:
            continue
        poly, b = regions[k], beta[k]
        for j in range(n):
            reach = max(reach, math.hypot(poly[j, 0] - c1, poly[j, 1] - c2))
        for j in range(1, n - 1):
            e1, e2 = poly[j] - poly[0], poly[j + 1] - poly[0]
            area = 0.5 * (e1[0] * e2[1] - e1[1] * e2[0])
            for i in range(4):
                y = poly[0] + bary[i][0] * e1 + bary[i][1] * e2
                tau = b[0] + b[1] * y[0] + b[2] * y[1]
                polar += area * weights[i] * tau * ((y[0] - c1) ** 2 + (y[1] - c2) ** 2)
    return polar, reach


@njit(cache=True)
def _in_cone(sigma_t, v_u, c1, c2, apex, band):
    """Whether the trial lies by more than ``band`` inside the hull of the disc
    ``{(V, ybar x V): |V| <= V_u}`` and the points ``+-apex`` (``(a, b, M)`` about the
    reference, ``M`` taken about ``ybar = (c1, c2)`` positive)."""
    t = (sigma_t[2] - (c1 * sigma_t[1] - c2 * sigma_t[0])) / apex[2]
    shrink = 1.0 - 2.0 * band
    if abs(t) >= shrink:
        return False
    radius = (1.0 - abs(t)) * v_u * shrink
    return math.hypot(sigma_t[0] - t * apex[0], sigma_t[1] - t * apex[1]) < radius


@njit(cache=True)
def inside_bicone(sigma_t, regions, counts, beta, band, acc):
    """Whether the trial lies inside ``K`` by more than ``band``, from inner sets: hulls of
    the sliding disc ``{(V, ybar x V): |V| <= V_u}`` (translations: every point slides along
    ``V``; ``ybar`` the centroid of the capacity) and two points of pure torsion about
    ``ybar``. First ``+-(0, 0, J / r)`` (the traction ``tau |y - ybar| / r`` across the
    radii: no net shear, as ``ybar`` is the centroid; moments only), then the support points
    of the twist about ``ybar`` (one support evaluation). Sufficient, not necessary."""
    v_u, c1, c2 = capacity_centroid(regions, counts, beta)
    if v_u <= 0.0:
        return False
    polar, reach = polar_capacity(regions, counts, beta, c1, c2)
    if polar > 0.0 and _in_cone(sigma_t, v_u, c1, c2, np.array((0.0, 0.0, polar / reach)), band):
        return True
    support(np.array((c2, -c1, 1.0)), regions, counts, beta, acc)
    a, b = acc[1], acc[2]
    apex = np.array((a, b, acc[3] - (c1 * b - c2 * a)))  # the twist's torsion about ybar
    return apex[2] > 0.0 and _in_cone(sigma_t, v_u, c1, c2, apex, band)


@njit(cache=True)
def project(sigma_t, C, regions, counts, beta, band, out_s, out_A, out_B, out_G):
    """Closest point of ``K`` to the trial ``sigma_t`` in the energy of ``C`` (module notes).

    Parameters
    ----------
    sigma_t : (3,) float64
        Trial ``(V1, V2, M3')`` about the reference point [N, N m].
    C : (3,) float64
        Elastic stiffnesses ``(k_t A, k_t A, k_t J_p)`` [N/m, N m/rad].
    regions, counts, beta
        The capacity of the joint (:func:`capacity_regions`).
    band : float
        Relative band below the limit that already counts as yielding [-].
    out_s : (3,) float64
        The returned ``(V1, V2, M3')``.
    out_A, out_B : (3, 3) float64
        ``d s / d sigma_t`` and the factor ``B`` of ``d s = B (dg / dbeta) d beta`` for a
        change of the capacity at the fixed trial.
    out_G : (3, 5) float64
        ``d g`` at the flow direction per change of ``(beta0, beta1, beta2)`` of the linear
        part and per move ``(delta1, delta2)`` of the reference point with the capacity
        fixed on the joint [N, N m per Pa, Pa/m, m].

    Returns
    -------
    plastic : bool
    """
    if sigma_t[0] == 0.0 and sigma_t[1] == 0.0 and sigma_t[2] == 0.0:
        out_s[:] = sigma_t  # the origin: inside whenever the joint has a capacity
        return False
    acc = np.empty(N_ACC)
    if inside_bicone(sigma_t, regions, counts, beta, band, acc):
        out_s[:] = sigma_t
        return False
    d, psi = _max_direction(sigma_t, C, regions, counts, beta, band, acc)
    if psi <= -band * acc[0]:
        out_s[:] = sigma_t
        return False
    if psi > 0.0:
        w = _minimise(sigma_t, C, psi * d, regions, counts, beta, acc)
        out_s[:] = acc[1:4]
        # B = C (C + H)^{-1}; H is symmetric
        out_B[:, :] = solve_stiffness(np.diag(C) + acc[4:13].reshape((3, 3)), np.diag(C)).T
    else:
        # on the boundary to within the band: the trial, with the tangent of continued flow
        # (the limit of C (C + H / s)^{-1} as s -> 0: H has the null vector d)
        w = d
        out_s[:] = sigma_t
        cd = C * d
        out_B[:, :] = np.outer(cd, d) / (d @ cd)
    out_A[:, :] = np.eye(3) - out_B
    out_G[:, :3] = acc[13:22].reshape((3, 3))
    # moving the reference by delta: h(w) -> h(w1 + omega delta2, w2 - omega delta1, omega),
    # M3' -> M3' - delta x V (H is homogeneous of degree -1, so d serves for w)
    H = acc[4:13].reshape((3, 3))
    out_G[:, 3] = -w[2] * H[:, 1]
    out_G[:, 4] = w[2] * H[:, 0]
    out_G[2, 3] -= acc[2]
    out_G[2, 4] += acc[1]
    return True
