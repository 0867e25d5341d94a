"""Small job texts shared by tests (not a test module)."""


def slope_job(*, duration: float, snapshots: int, series_every: int = 2) -> str:
    """A 6 m x 4 m sheet of Table 4 bonds carried at 1 m/s onto a 45-degree plane: clear of the sheet
    at t = 0 and touched within 0.05 s."""
    return f"""\
[run]
duration = {duration}
series_every = {series_every}
snapshots = {snapshots}
[water]
density = 1035.0
current = [1.0, 0.0]
[ice]
length = 6.0
width = 4.0
velocity = [1.0, 0.0]
[bond]
normal_stiffness = 1.72e7
normal_strength = 1.5e6
friction = 0.3
[[walls]]
name = "slope"
type = "plane"
point = [6.53, 0.0, 0.0]
normal = [-0.7071068, 0.0, 0.7071068]
"""
