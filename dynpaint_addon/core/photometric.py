"""Normal maps from images of the subject lit from known sides (docs/shape-from-painting.md).

Lighting profiles (photometric stereo, Sprite Lamp's workflow): 2–5 images of the same
subject, painted or photographed lit from the left, right, top, bottom and front. A matte
surface of albedo ρ shows I_k = ρ·(N·L_k) under light k; per pixel the vector b = ρN that
best explains the profiles (least squares) gives N = b/|b|:

    b = argmin Σ_k w_k (I_k − L_k·b)² + μ |b − blur(b)|²

w_k down-weights a profile where the pixel is dark in it (in its shadow, attached or cast,
where I_k = ρ·max(N·L_k, 0) says nothing about N). With 4–5 profiles the data decide; with
2–3 some direction is unseen (left and right alone never see N.y) and the smoothness prior
μ fills it from the neighbours, starting from the front-facing normal.

The red/green photograph (the paper's shortcut, §2 of its shape-image section): a subject lit
by a red light from one side and a green light from the top *is* a normal map's x and y:
N.x = 2R − 1, N.y = 2G − 1, N.z = √(1 − x² − y²), sides settable.

    >>> import numpy as np
    >>> n = np.array([[[0.3, -0.2, 0.933]]]) / np.linalg.norm([0.3, -0.2, 0.933])
    >>> lights = profile_directions(("left", "right", "top", "bottom"), 45)
    >>> shots = {k: np.clip(n @ l, 0, None) for k, l in lights.items()}
    >>> np.round(normals_from_profiles(shots, 45), 3)[0, 0].tolist()
    [0.3, -0.2, 0.933]
"""
import numpy as np

from .sampling import gaussian_blur

SIDES = ("left", "right", "top", "bottom", "front")
DARK = 0.015        # a profile this dark (× the pixel's brightest) is taken as shadowed
SHADOW_MARGIN = 0.05  # … or this much darker than the other profiles predict (4+ profiles)


def profile_directions(sides, elevation_deg):
    """Unit vectors toward each side's light, `elevation_deg` above the painting (front: +z)."""
    e = np.radians(elevation_deg)
    c, s = np.cos(e), np.sin(e)
    table = {"left": (-c, 0, s), "right": (c, 0, s), "top": (0, c, s), "bottom": (0, -c, s),
             "front": (0, 0, 1)}
    return {side: np.array(table[side], dtype=np.float64) for side in sides}


def _fill(values, known, sigma_px):
    """`values` where `known`, elsewhere their Gaussian-weighted mean around (else the median
    of all known values)."""
    if not known.any():
        return np.zeros_like(values)
    num = gaussian_blur(np.where(known, values, 0), sigma_px)
    den = gaussian_blur(known.astype(np.float64), sigma_px)
    far = float(np.median(values[known]))
    return np.where(known, values, np.where(den > 1e-3, num / np.maximum(den, 1e-12), far))


def _solve(weight, shots, lit):
    """Per pixel least squares b of the weighted profiles, and whether three of them that are
    not in one plane decide it."""
    a = np.einsum("hwk,ki,kj->hwij", weight, lit, lit)
    b = np.einsum("hwij,hwj->hwi", np.linalg.inv(a + 1e-9 * np.eye(3)),
                  np.einsum("hwk,ki->hwi", weight * shots, lit))
    return b, ((weight > 0.5).sum(-1) >= 3) & (np.linalg.det(a) > 1e-3)


def _drop_shadowed(shots, weight, lit, brightest, margin=SHADOW_MARGIN):
    """Where four or more profiles see a pixel, the one far darker than the others predict
    (a cast or soft shadow: painted shadows are seldom black) is dropped: leave each out in
    turn, keep the leave-one-out that explains the pixel, drop the profile it predicts
    brighter than shown by more than `margin` × the pixel's brightest."""
    seen = (weight > 0.5).sum(-1)
    deficits = []
    for k in range(lit.shape[0]):
        others = weight.copy()
        others[..., k] = 0
        b, ok = _solve(others, shots, lit)
        deficits.append(np.where(ok & (weight[..., k] > 0.5), b @ lit[k] - shots[..., k], -np.inf))
    deficits = np.stack(deficits, -1)
    worst = deficits.argmax(-1)
    drop = (seen >= 4) & (np.take_along_axis(deficits, worst[..., None], -1)[..., 0]
                          > margin * brightest)
    kept = np.take_along_axis(weight, worst[..., None], -1)
    out = weight.copy()
    np.put_along_axis(out, worst[..., None], np.where(drop[..., None], 0.0, kept), -1)
    return out


def _two_lit(shots, weight, lit, albedo, around):
    """b for pixels seen by exactly two profiles a, b: on the line of their two equations,
    b = b0 + t·(L_a × L_b), at the albedo |b| = ρ of the pixels around, on the side that keeps
    the shadowed profiles in shadow (N·L ≤ 0 there) and, where both do, nearer the normals
    `around` it."""
    order = np.argsort(-weight, axis=-1)
    la, lb = lit[order[..., 0]], lit[order[..., 1]]
    ia = np.take_along_axis(shots, order[..., :1], -1)[..., 0]
    ib = np.take_along_axis(shots, order[..., 1:2], -1)[..., 0]
    aa, ab, bb = (la * la).sum(-1), (la * lb).sum(-1), (lb * lb).sum(-1)
    det = aa * bb - ab * ab
    alpha = (bb * ia - ab * ib) / det
    beta = (aa * ib - ab * ia) / det
    b0 = alpha[..., None] * la + beta[..., None] * lb
    u = np.cross(la, lb)
    u /= np.linalg.norm(u, axis=-1, keepdims=True)
    t = np.sqrt(np.clip(albedo ** 2 - (b0 * b0).sum(-1), 0, None))[..., None]
    shadowed = weight < 0.5

    def cost(cand):
        return np.sum(np.where(shadowed, np.clip(cand @ lit.T, 0, None), 0), -1) \
            - 0.05 * np.sum(cand * around, -1)             # a tie: the one like its neighbours
    plus, minus = b0 + t * u, b0 - t * u
    return np.where((cost(minus) < cost(plus))[..., None], minus, plus)


def normals_from_profiles(profiles, elevation_deg=45.0, smoothness=0.05, iterations=30):
    """Unit normals (H, W, 3) from {side: (H, W) linear luminance} → y-up normal field.

    A pixel lit in three or more profiles: least squares. In exactly two (the rest in its
    shadow): completed at its neighbours' albedo (`_two_lit`). In fewer, or where only left
    and right (or top and bottom) were given: the smoothness prior, μ = `smoothness` × the
    pixel's brightness², `iterations` fixed-point steps from the front-facing normal.
    """
    sides = [s for s in SIDES if s in profiles]
    if len(sides) < 2:
        raise ValueError(f"lighting profiles: need at least 2 of {', '.join(SIDES)}, "
                         f"got {', '.join(sides) or 'none'}")
    dirs = profile_directions(sides, elevation_deg)
    shots = np.stack([np.asarray(profiles[s], np.float64) for s in sides], axis=-1)
    shots = np.where(np.isfinite(shots), np.clip(shots, 0, None), 0)
    lit = np.stack([dirs[s] for s in sides])                      # (K, 3)
    brightest = shots.max(axis=-1)
    # shadowed profiles weigh 0 below DARK × the pixel's brightest, 1 above twice that
    u = np.clip((shots / np.maximum(brightest, 1e-12)[..., None] - DARK) / DARK, 0, 1)
    weight = np.where(brightest[..., None] > 0, u * u * (3 - 2 * u), 0)
    for _ in range(len(sides) - 3):           # soft shadows: darker than the others predict
        weight = _drop_shadowed(shots, weight, lit, brightest)
    seen = (weight > 0.5).sum(-1)
    b, determined = _solve(weight, shots, lit)
    rank3 = np.linalg.matrix_rank(lit) == 3
    b = np.where(determined[..., None], b, 0)
    if rank3:
        two = seen == 2
        if two.any():
            albedo = _fill(np.linalg.norm(b, axis=-1), determined, 4.0)
            unit = b / np.maximum(np.linalg.norm(b, axis=-1, keepdims=True), 1e-12)
            around = np.stack([_fill(unit[..., i], determined, 4.0) for i in range(3)], -1)
            b = np.where(two[..., None], _two_lit(shots, weight, lit, albedo, around), b)
        rest = seen < 2
    else:
        rest = np.ones(brightest.shape, bool)
    if rest.any():
        weight = np.maximum(weight, 0.2)        # every profile says a little
        mu = smoothness * np.maximum(brightest, 1e-6) ** 2
        a = np.einsum("hwk,ki,kj->hwij", weight, lit, lit) + mu[..., None, None] * np.eye(3)
        inverse = np.linalg.inv(a)
        rhs = np.einsum("hwk,ki->hwi", weight * shots, lit)
        prior = np.where(rest[..., None], brightest[..., None] * np.array([0.0, 0.0, 1.0]), b)
        for _ in range(iterations):
            solved = np.einsum("hwij,hwj->hwi", inverse, rhs + mu[..., None] * prior)
            prior = np.where(rest[..., None], gaussian_blur(np.where(rest[..., None], solved, b),
                                                            1.0), b)
        b = np.where(rest[..., None], solved, b)
    length = np.linalg.norm(b, axis=-1, keepdims=True)
    front = np.zeros_like(b)
    front[..., 2] = 1
    return np.where(length > 1e-9, b / np.maximum(length, 1e-12), front)


def normals_from_rg_photo(rgb, red_from="right", green_from="top"):
    """The paper's red/green photograph → unit normals: N.x = ±(2R − 1), N.y = ±(2G − 1),
    N.z = √(1 − x² − y²) (x, y scaled back inside the unit circle where they leave it)."""
    rgb = np.asarray(rgb, np.float64)
    if red_from not in ("right", "left") or green_from not in ("top", "bottom"):
        raise ValueError("the red light comes from the right or left, the green from the top "
                         "or bottom")
    x = (2 * rgb[..., 0] - 1) * (1 if red_from == "right" else -1)
    y = (2 * rgb[..., 1] - 1) * (1 if green_from == "top" else -1)
    r = np.sqrt(x * x + y * y)
    shrink = np.where(r > 1, 1 / np.maximum(r, 1e-12), 1)
    x, y = x * shrink, y * shrink
    z = np.sqrt(np.clip(1 - x * x - y * y, 0, None))
    return np.stack([x, y, z], axis=-1)
