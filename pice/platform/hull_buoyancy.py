"""Hull buoyancy: submerged volume and centre of buoyancy of a hull mesh and its braces (Eqs. 12-14
of Zhu & Ji 2022), and the buoyancy force and moment on the body.

The mesh (Eq. 12): each triangle (in space coordinates) is clipped at the water plane z = level and
the part below is fanned into triangles; each forms a tetrahedron with a reference point ON the
water plane, whose signed volume is (1/6) (a - p) . ((b - p) x (c - p)) (Eq. 12). The missing lid of
the clipped mesh lies in the water plane, so its tetrahedra have zero volume: the sum over the
clipped triangles is the exact submerged volume of the closed mesh, and the volume-weighted
tetrahedron centroids give the centre of buoyancy. Outward normals (counter-clockwise seen from
outside) give positive volume. Braces are cylinders sliced along their axes (Eqs. 13-14,
``brace_submerged``), given as records of BRACE_RECORD; the body's buoyancy acts at the combined
centre of mesh and braces.

The numba kernels (``submerged_volume``, ``brace_submerged``, ``transform``) are pure functions of
arrays and scalars (no MPI, no I/O); ``submerged`` and ``buoyancy`` are their Python owners, called
by platform.rigid_body.RigidBody and, before a body is built, by platform.build for its
"balance" mass.
"""

import math

import numpy as np
from numba import njit

from ..kernels import JIT
from ..kernels.geometry import rotation_matrix

BRACE_SLICES = 64  # default slices per brace along its axis (Eq. 13)

# One cylindrical brace in the body frame: the ends of its axis p0, p1 (3,) [m] and its radius [m].
BRACE_RECORD = np.dtype([("p0", np.float64, (3,)), ("p1", np.float64, (3,)), ("radius", np.float64)])


@njit(**JIT)
def _accumulate(p, a, b, c, acc):
    """Add the tetrahedron (p, a, b, c): acc[0] += V, acc[1:4] += V * centroid."""
    ax, ay, az = a[0] - p[0], a[1] - p[1], a[2] - p[2]
    bx, by, bz = b[0] - p[0], b[1] - p[1], b[2] - p[2]
    cx, cy, cz = c[0] - p[0], c[1] - p[1], c[2] - p[2]
    vol = (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0
    acc[0] += vol
    for k in range(3):
        acc[1 + k] += vol * 0.25 * (p[k] + a[k] + b[k] + c[k])


@njit(**JIT)
def submerged_volume(vertices, triangles, level):
    """(volume [m^3], centre of buoyancy (3,) [m]) of the part of a closed mesh below z = level.

    vertices: (nv, 3) space coordinates [m]; triangles: (nt, 3) vertex indices, outward orientation.
    The centre is NaN when nothing is submerged.
    """
    acc = np.zeros(4)
    # reference point on the water plane, above the mesh's mean position (keeps tetrahedra small)
    p = np.zeros(3)
    for k in range(2):
        p[k] = vertices[:, k].mean()
    p[2] = level
    poly = np.empty((4, 3))
    for t in range(triangles.shape[0]):  # (no array is made per triangle: 30 -> 4 us for the buoy's 512)
        npoly = 0
        for e in range(3):  # Sutherland-Hodgman against the half-space z <= level
            ia = triangles[t, e]
            ib = triangles[t, (e + 1) % 3]
            a_in = vertices[ia, 2] <= level
            b_in = vertices[ib, 2] <= level
            if a_in:
                for k in range(3):
                    poly[npoly, k] = vertices[ia, k]
                npoly += 1
            if a_in != b_in:
                s = (level - vertices[ia, 2]) / (vertices[ib, 2] - vertices[ia, 2])
                for k in range(2):
                    poly[npoly, k] = vertices[ia, k] + s * (vertices[ib, k] - vertices[ia, k])
                poly[npoly, 2] = level
                npoly += 1
        for k in range(1, npoly - 1):
            _accumulate(p, poly[0], poly[k], poly[k + 1], acc)
    if acc[0] == 0.0:
        return 0.0, np.full(3, np.nan)
    return acc[0], acc[1:] / acc[0]


@njit(**JIT)
def transform(vertices_body, q_matrix, position):
    """Body-frame vertices -> space frame: x = R x_B + position."""
    out = np.empty_like(vertices_body)
    for i in range(vertices_body.shape[0]):
        for k in range(3):
            out[i, k] = (q_matrix[k, 0] * vertices_body[i, 0] + q_matrix[k, 1] * vertices_body[i, 1]
                         + q_matrix[k, 2] * vertices_body[i, 2] + position[k])
    return out


@njit(**JIT)
def brace_axis(p0, p1):
    """(axis p1 - p0 (3,) [m], its length [m], cos of its inclination to the water plane, the unit
    downward direction of its cross-sections (3,): perpendicular to the axis, in the vertical plane
    through it) of a brace from p0 to p1."""
    axis = p1 - p0
    length = math.sqrt(axis[0] ** 2 + axis[1] ** 2 + axis[2] ** 2)
    cos_t = math.sqrt(axis[0] ** 2 + axis[1] ** 2) / length
    a = axis / length
    down = np.array([a[2] * a[0], a[2] * a[1], a[2] * a[2] - 1.0])  # -(z - (z.a) a)
    dn = math.sqrt(down[0] ** 2 + down[1] ** 2 + down[2] ** 2)
    if dn > 0.0:
        down /= dn
    return axis, length, cos_t, down


@njit(**JIT)
def slice_section(h, cos_t, R):
    """(submerged area [m^2], drop [m]) of a brace's cross-section of radius R [m] whose axis point
    lies h [m] above the water plane, the brace inclined at theta to it (cos_t = cos theta): the
    circular segment below the chord d = h / cos theta above the centre (Eq. 14), and its centroid's
    distance below the centre along the section's downward direction (``brace_submerged``)."""
    if cos_t < 1e-12:  # vertical brace: the slice is wholly wet or dry
        return (math.pi * R * R if h <= 0.0 else 0.0), 0.0
    d = h / cos_t
    if d <= -R:
        return math.pi * R * R, 0.0
    if d >= R:
        return 0.0, 0.0
    area = R * R * math.acos(d / R) - d * math.sqrt(R * R - d * d)
    # centroid of the circular segment below the chord, measured from the centre
    drop = 2.0 * (R * R - d * d) ** 1.5 / (3.0 * area) if area > 0.0 else 0.0
    return area, drop


@njit(**JIT)
def brace_submerged(p0, p1, radius, level, nseg):
    """(submerged volume [m^3], centroid (3,) [m]) of a cylindrical brace from p0 to p1 (Eqs. 13-14).

    The brace is cut into nseg slices along its axis; each slice contributes its length times the
    submerged area of its cross-section (Eq. 14), a circular segment below a chord at the height
    d = h / cos(theta) above the centre, theta the brace's inclination to the water plane:
    A = pi R^2 (d <= -R), R^2 arccos(d/R) - d sqrt(R^2 - d^2) (|d| < R), 0 (d >= R). (The paper's
    Eq. 14 prints arccos(h/cos theta) without the /R.) The slice centroid is taken on its axis,
    shifted by the segment centroid 2 (R^2 - d^2)^(3/2) / (3 A) along the section's downward
    direction (perpendicular to the axis, in the vertical plane through it).
    """
    axis, length, cos_t, down = brace_axis(p0, p1)
    dl = length / nseg
    vol = 0.0
    mom = np.zeros(3)
    R = radius
    for k in range(nseg):
        c = p0 + (k + 0.5) / nseg * axis
        area, drop = slice_section(c[2] - level, cos_t, R)
        dv = area * dl
        vol += dv
        for q in range(3):
            mom[q] += dv * (c[q] + drop * down[q])
    if vol == 0.0:
        return 0.0, np.full(3, np.nan)
    return vol, mom / vol


def hull_in_space(vertices, *, position, attitude) -> np.ndarray:
    """(nv, 3) body-frame hull vertices at the pose (position [m], unit quaternion), space frame [m]."""
    return transform(vertices, rotation_matrix(attitude), position)


def submerged(vertices, triangles, braces, brace_slices: int = BRACE_SLICES, *, position, attitude,
              level: float) -> tuple[float, np.ndarray]:
    """(submerged volume [m^3], centre of buoyancy (3,) [m], space frame) of a hull at a pose: the
    clipped mesh (Eq. 12) plus the braces, (k,) BRACE_RECORD in the body frame (p0, p1, radius) [m],
    sliced along their axes (Eqs. 13-14). NaN centre when dry."""
    vol, cob = submerged_volume(hull_in_space(vertices, position=position, attitude=attitude), triangles, level)
    if len(braces) == 0:
        return vol, cob
    mom = vol * cob if vol > 0.0 else np.zeros(3)
    vol, mom = _add_braces(vol, mom, braces, rotation_matrix(attitude), np.asarray(position, float), level,
                           int(brace_slices))
    if vol <= 0.0:
        return 0.0, np.full(3, np.nan)
    return vol, mom / vol


@njit(**JIT)
def _add_braces(vol, mom, braces, R, position, level, slices):
    """(volume [m^3], first moment (3,) [m^4]) of mesh and braces: each brace of the body frame placed
    by R and position and sliced (``brace_submerged``), added to the mesh's vol and mom."""
    mom = mom.copy()
    for k in range(braces.shape[0]):
        p0 = R @ braces[k]["p0"] + position
        p1 = R @ braces[k]["p1"] + position
        vb, cb = brace_submerged(p0, p1, braces[k]["radius"], level, slices)
        if vb > 0.0:
            vol += vb
            for q in range(3):
                mom[q] += vb * cb[q]
    return vol, mom


def buoyancy(vertices, triangles, braces, brace_slices: int = BRACE_SLICES, *, position, attitude, rho_w: float,
             g: float, level: float) -> tuple[np.ndarray, np.ndarray, float]:
    """(force [N], moment about ``position`` (the CG) [N m], submerged volume [m^3]) of the buoyancy
    rho_w g V of hull mesh and braces, acting at their combined centre of buoyancy."""
    vol, cob = submerged(vertices, triangles, braces, brace_slices, position=position, attitude=attitude,
                         level=level)
    if vol <= 0.0:
        return np.zeros(3), np.zeros(3), 0.0
    fz = rho_w * g * vol
    arm = cob - position
    return np.array([0.0, 0.0, fz]), np.array([arm[1] * fz, -arm[0] * fz, 0.0]), vol  # arm x (0, 0, fz)
