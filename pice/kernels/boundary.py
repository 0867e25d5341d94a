"""Spring boundary: edge elements tied to anchors that move with the far-field ice."""

import math

from numba import njit

from . import JIT


@njit(**JIT)
def spring_boundary(nlocal, x, v, mass, anchor, stiffness, damping_ratio, velocity, shift, force):
    """F_d = -k_d (x_d - (a_d + s_d)) - 2 zeta sqrt(m k_d) (v_d - u_d) on every owned element, in each
    direction d with k_d > 0.

    anchor (n,3): the element's position at t = 0 [m]; stiffness (n,3) [N/m] per direction (0: free);
    velocity (3,): the anchors' velocity u [m/s]; shift (3,): how far they have moved since t = 0 [m]
    (u t for a far field at constant speed). Returns the total force on the tied elements [N] (x
    component), the far field's push on the sheet.
    """
    total = 0.0
    for i in range(nlocal):
        for d in range(3):
            k = stiffness[i, d]
            if k <= 0.0:
                continue
            c = 2.0 * damping_ratio * math.sqrt(mass[i] * k)
            f = -k * (x[i, d] - anchor[i, d] - shift[d]) - c * (v[i, d] - velocity[d])
            force[i, d] += f
            if d == 0:
                total += f
    return total
