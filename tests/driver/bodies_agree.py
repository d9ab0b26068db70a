"""The comparison of two runs' final rigid bodies (DIR/bodies.csv of the fdem driver), shared by
ranks_agree.py and walls_agree.py."""
import math


def compare(a, b, tol, what):
    """a, b: the rows of two bodies.csv files (header first). Returns the list of failures:
    the same bodies in the same order, positions within tol (m), velocities within 1000 tol
    (m/s), and something moving faster than 1 cm/s (else the scene tests nothing); prints the
    measured differences, `what` naming the two runs."""
    fail = []
    if a[0] != b[0] or a[0][:5] != ["id", "name", "x", "y", "z"]:
        fail.append(f"bodies.csv headers: {a[0]} / {b[0]}")
    if [r[:2] for r in a[1:]] != [r[:2] for r in b[1:]] or len(a) < 3:
        fail.append(f"the bodies (ids and names) differ between {what}, or there are fewer than 2")
        return fail
    dx = max(math.dist([float(x) for x in u[2:5]], [float(x) for x in v[2:5]]) for u, v in zip(a[1:], b[1:]))
    dv = max(math.dist([float(x) for x in u[5:8]], [float(x) for x in v[5:8]]) for u, v in zip(a[1:], b[1:]))
    moved = max(math.hypot(*[float(x) for x in u[5:8]]) for u in a[1:])
    print(f"{len(a) - 1} bodies: {what}, max |dx| {dx:.3g} m (bound {tol:g}), max |dv| {dv:.3g} m/s (bound {tol * 1e3:g}); largest speed {moved:.3g} m/s")
    if not dx <= tol:
        fail.append(f"positions differ by {dx:.3g} m > {tol:g}")
    if not dv <= tol * 1e3:
        fail.append(f"velocities differ by {dv:.3g} m/s > {tol * 1e3:g}")
    if not moved > 0.01:
        fail.append("nothing moves: the scene tests nothing")
    return fail
