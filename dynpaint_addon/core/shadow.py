"""cos-θ shadows (pipeline.md §6): diffuse, cast shadow and a subsurface look in one number.

For a surface point P_S with normal N_S, start at P0 = P_S − d·N_S, march P(s) = P0 + s·L and
measure r, the length of the ray inside the relief. t = d / max(r, d). On a plane r = d/cos θ,
so t = cos θ exactly, for any d.

This is the straightforward, correct march (one bilinear gather per pixel per step): the
reference every faster method (crossings.py) is measured against, and nothing else; which
method bakes at which quality level is bake.py's choice. Everything inside works in pixels.
"""
from dataclasses import dataclass

import numpy as np

from .lights import light_vectors
from .path_bounds import BOUNDS, PATH_SEGMENTS
from .sampling import pixel_centres, sample_bilinear, sample_extend

OCCUPANCIES = ("linear", "midpoint")
MAX_STEPS_PER_PIXEL = 4  # more steps than this per pixel of march length add nothing (bilinear H)


@dataclass
class ShadowStats:
    """What a bake did, for `bake-shadow -v` and the benchmarks."""
    steps: int = 0
    max_march_px: float = 0.0
    method: str = "march"       # or "exact crossings" (suns), "aimed crossings" (point
    #                             lights; core/crossings.py)
    size: tuple = (0, 0)        # (H, W) the bake ran at before upsampling

    def settings(self):
        h, w = self.size
        how = f"K = {self.steps} march" if self.method == "march" else self.method
        return f"{how} at {w}×{h}"


def occupancy_fraction(delta0, delta1, occupancy="linear"):
    """Inside fraction of one step from δ = H − z at its ends (§6).

    'linear': the crossing is linearly interpolated: (δ0⁺ + δ1⁺)/(|δ0| + |δ1|) (1 when both are
    inside, 0 when both outside). 'midpoint': the paper's binary count of the step's midpoint
    (sign of the mean), error ≈ a·cos²θ/(2d); a fallback only.
    """
    if occupancy == "linear":
        pos = np.maximum(delta0, 0) + np.maximum(delta1, 0)
        total = np.abs(delta0) + np.abs(delta1)
        return np.where(total > 0, pos / np.where(total > 0, total, 1), 0)
    if occupancy == "midpoint":
        return ((delta0 + delta1) > 0).astype(delta0.dtype)
    raise ValueError(f"unknown occupancy {occupancy!r} (expected one of {', '.join(OCCUPANCIES)})")


def exit_distance(x0, y0, lx, ly, height, width):
    """Distance along (lx, ly) from (x0, y0) until the ray leaves the box of pixel centres
    [½, W − ½] × [½, H − ½] (0 if already outside). Bilinear lookups are exact inside that box
    only (beyond it "extend" flattens the relief), so the march stops there and the tail
    extrapolates the rest: that keeps tilted planes exact up to the border.
    """
    lo = 0.5
    big = np.asarray(np.inf, dtype=x0.dtype)
    with np.errstate(divide="ignore", invalid="ignore"):
        tx = np.where(lx > 0, (width - lo - x0) / lx, np.where(lx < 0, (lo - x0) / lx, big))
        ty = np.where(ly > 0, (height - lo - y0) / ly, np.where(ly < 0, (lo - y0) / ly, big))
    return np.where(inside_box(x0, y0, height, width), np.maximum(np.minimum(tx, ty), 0), 0)


def inside_box(x0, y0, height, width):
    return (x0 >= 0.5) & (x0 <= width - 0.5) & (y0 >= 0.5) & (y0 <= height - 0.5)


def vertical_cos_theta(normals, offset, *, heights_px=None):
    """t for a sun straight above (L = (0, 0, 1), §6), in closed form: what the march
    computes, without marching. The ray from P0 = P_S − d·N_S rises vertically, so along it
    the relief stays H(P0.xy): on a height map r = max(H(P0.xy) − P0.z, 0) (the tangent
    plane of P_S where P0 lies outside the box of pixel centres, as the march's tail has it);
    on a normal map the height rebuilt along the ray stays that of P_S's tangent plane, so
    t = N.z. Requires d > 0."""
    f = normals.dtype.type
    nz = normals[..., 2]
    if heights_px is None:
        return np.clip(nz, 0, 1).astype(normals.dtype, copy=False)
    h, w = normals.shape[:2]
    d = f(float(offset) * w)
    x, y = pixel_centres(h, w, f)
    x0, y0 = x - d * normals[..., 0], y - d * normals[..., 1]
    z0 = heights_px.astype(normals.dtype, copy=False) - d * nz
    inside = inside_box(x0, y0, h, w)
    t = np.where(inside, d / np.maximum(sample_bilinear(heights_px, x0, y0, "extend") - z0, d),
                 nz)
    return np.clip(np.where(np.isfinite(t), t, 0), 0, 1).astype(normals.dtype, copy=False)


class BakeCancelled(Exception):
    """A bake was superseded (its `cancel` callback said so) before it finished."""


BAND_PIXELS = 1 << 20    # pixels marched at once: bounds the per-step state at any image size


def cos_theta_shadow(normals, light, offset, steps, *, heights_px=None, slopes=None,
                     occupancy="linear", reach=np.inf, stats=None, cancel=None, progress=None,
                     bounds="path"):
    """The raw cos-θ term t = d / max(r, d) ∈ [0, 1] for one light (§6), shape (H, W).

    normals: unit normals (H, W, 3) (N.z ≥ z_min, §2), in the dtype to compute in.
    light: core.lights.Light (sun or point; positions in image widths from the centre).
    offset: d in image widths. steps: K (≥ 0).
    heights_px: the relief z = h·H in pixels, for height maps; or
    slopes: (H, W, 2) implied gradient −N.xy/N.z, for normal maps (height is reconstructed
    along each ray only, so non-conservative maps work).

    Edge cases (§6, §14): a sun with L.z ≤ 0 gives t = 0; a point light inside the relief caps
    the segment at the light; d = 0 gives max(N·L, 0) × hard visibility; K = 0 marches nothing
    and extrapolates along the tangent plane (t = N·L on any surface); K is capped at
    MAX_STEPS_PER_PIXEL steps per pixel of the longest march, so a huge K stays finite in time.
    reach (image widths, normal maps only; §6 "Reach"): the rebuilt relief is felt up to this
    far along the ray, beyond it the surface is P_S's tangent plane (r = r(0…R) +
    max(d/N·L − R, 0)): a plane stays exact, and an impossible figure's slopes, which rebuild
    heights that never come back down, cast no shadow longer than R.
    cancel: optional callable, asked before every step; True aborts with BakeCancelled (a newer
    bake supersedes this one). progress: optional callable(fraction done), once per band.
    bounds: where a ray's march ends — "path": past the last point of its own path the relief
    could still reach (path_bounds.py: a part that does not change is marched the same
    whatever the rest of the image does, §16); "image": the whole image's highest point or
    steepest slope (as before; the benchmarks' baseline).

    Rows are marched in bands of about BAND_PIXELS pixels (each pixel's ray is independent;
    the relief is sampled whole), so memory beyond the inputs and the result stays bounded.
    """
    if (heights_px is None) == (slopes is None):
        raise ValueError("give exactly one of heights_px (height map) or slopes (normal map)")
    h, w = normals.shape[:2]
    rows = max(1, BAND_PIXELS // max(w, 1))
    bands = [(r, min(h, r + rows)) for r in range(0, h, rows)] or [(0, 0)]
    ctx = _MarchInputs(normals, light, offset, heights_px, slopes, reach, bounds)
    # K is the same for every band (it follows the longest march of the whole image), so a
    # banded bake equals an unbanded one bit for bit. The first band's setup is kept: up to
    # BAND_PIXELS pixels it is the only band.
    first = _ray_setup(ctx, *bands[0])
    max_ell = max([float(first["ell"].max(initial=0.0))]
                  + [float(_ray_setup(ctx, r0, r1)["ell"].max(initial=0.0))
                     for r0, r1 in bands[1:]])
    steps = max(0, int(steps))
    k_eff = min(steps, max(1, int(np.ceil(MAX_STEPS_PER_PIXEL * max_ell)))) if steps else 0
    if stats is not None:
        stats.steps, stats.max_march_px = k_eff, max_ell
    out = np.empty((h, w), normals.dtype)
    for i, (r0, r1) in enumerate(bands):
        setup = first if i == 0 else _ray_setup(ctx, r0, r1)
        out[r0:r1] = _march_band(ctx, setup, k_eff, occupancy, cancel)
        if progress is not None:
            progress((i + 1) / len(bands))
    return out


@dataclass
class _MarchInputs:
    """What every band of a march shares: the whole relief and the light."""
    normals: np.ndarray
    light: object
    offset: float
    heights_px: object
    slopes: object
    reach: float = np.inf
    bounds: str = "path"

    def __post_init__(self):
        self.dtype = self.normals.dtype
        self.f = self.dtype.type
        self.h, self.w = self.normals.shape[:2]
        self.zs = self.heights_px.astype(self.dtype, copy=False) if self.heights_px is not None \
            else None
        self.d = self.f(max(0.0, float(self.offset)) * self.w)
        self.reach_px = max(0.0, float(self.reach)) * self.w if self.slopes is not None \
            else np.inf
        # what each ray's path can meet (path_bounds): its relief, or its steepest slope
        field = self.zs if self.zs is not None else \
            np.hypot(self.slopes[..., 0], self.slopes[..., 1]).astype(self.dtype, copy=False)
        self.bounds = BOUNDS[self.bounds](field) if field.size else None


def _path_pieces(c, x0, y0, lx, ly, span):
    """The bounds of c's field over each ray's path (path_bounds), piece by piece, and the
    length along the ray (s) of one piece; span: how far each ray can go (s)."""
    lxy = np.hypot(lx, ly)
    with np.errstate(divide="ignore", invalid="ignore"):
        ux, uy = np.where(lxy > 0, lx / lxy, 0), np.where(lxy > 0, ly / lxy, 0)
        length = np.where(lxy > 0, np.minimum(span, c.f(4 * (c.h + c.w))) * lxy, 0)
    return c.bounds.along(x0, y0, ux, uy, length), span / c.f(PATH_SEGMENTS)


# How far above a path's bound a march ends (px): a ray ending exactly at the bound could read
# as still inside by float rounding, and its tail would then darken a lit edge
CLEAR_PX = 0.01


def _relief_ceiling(c, x0, y0, z0, lx, ly, lz, span):
    """How far along each ray it can still be inside the relief (s): past the last piece of
    its path whose bound the ray has not yet risen above (lz ≤ 0: its whole span)."""
    pieces, step = _path_pieces(c, x0, y0, lx, ly, span)
    top = np.zeros_like(z0)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for j, bound in enumerate(pieces):
            start = np.zeros_like(z0) if j == 0 else c.f(j) * step
            above_at = (bound + c.f(CLEAR_PX) - z0) / lz   # where the ray is clear of it
            met = z0 + start * lz < bound
            top = np.where(met, np.maximum(top, np.minimum(c.f(j + 1) * step, above_at)), top)
    return np.where(lz > 0, top, np.inf)


def _slope_ceiling(c, x0, y0, lx, ly, lz, span, delta):
    """A normal map's ray (§6, height rebuilt along it): the rebuilt height climbs at most
    S·|L.xy| per unit s, S the steepest slope on the ray's path; once the ray outclimbs that
    it can never be inside again."""
    pieces, _ = _path_pieces(c, x0, y0, lx, ly, span)
    steepest = np.zeros_like(delta)
    for bound in pieces:
        steepest = np.maximum(steepest, bound)
    climb = lz - steepest * np.hypot(lx, ly)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(climb > 0, (delta + c.f(CLEAR_PX)) / climb, np.inf)


def _ray_setup(c, r0, r1):
    """Per-pixel start, direction and march length of rows r0 … r1 − 1."""
    f, d, h, w, light = c.f, c.d, c.h, c.w, c.light
    x, y = pixel_centres(h, w, f)
    x, y = x[r0:r1], y[r0:r1]
    n = c.normals[r0:r1]
    zs = c.zs[r0:r1] if c.zs is not None else np.zeros((r1 - r0, w), c.dtype)
    nx, ny, nz = n[..., 0], n[..., 1], n[..., 2]
    # P0 = P_S − d·N_S
    x0 = x - d * nx
    y0 = y - d * ny
    z0 = zs - d * nz
    # §6 Which ray: a sun's direction; for a point light the segment from P0 to the light
    lvec, light_dist = light_vectors(light, x0, y0, z0, c.dtype, image_size=(h, w))
    lx, ly, lz = lvec[..., 0], lvec[..., 1], lvec[..., 2]
    ndl = nx * lx + ny * ly + nz * lz
    to_edge = exit_distance(x0, y0, lx, ly, h, w)
    span = to_edge if light_dist is None else np.minimum(to_edge, light_dist)
    span = np.minimum(span, c.f(c.reach_px)) if np.isfinite(c.reach_px) else span
    h_rec = None
    if c.zs is not None:
        # δ0 from the relief where it is known; on the tangent plane of P_S (d/N.z) where P0
        # lies outside the box of pixel centres (border pixels whose normal points outward).
        delta = np.where(inside_box(x0, y0, h, w), sample_bilinear(c.zs, x0, y0, "extend") - z0,
                         d / nz)
        ell_top = _relief_ceiling(c, x0, y0, z0, lx, ly, lz, span)
    else:
        # Start on the tangent plane of P_S: H(P0.xy) = d|N.xy|²/N.z, δ0 = d/N.z.
        h_rec = d * (nx * nx + ny * ny) / nz
        delta = h_rec - z0
        ell_top = _slope_ceiling(c, x0, y0, lx, ly, lz, span, delta)
    ell = np.minimum(to_edge, ell_top)
    if light_dist is not None:
        ell_light = light_dist                  # the aimed ray ends at the light
        stopped_by_light = ell_light <= ell
        ell = np.minimum(ell, ell_light)
    else:
        ell_light = None
        stopped_by_light = np.zeros(x.shape, bool)
    by_reach = ell > c.reach_px            # §6 Reach: beyond it, P_S's tangent plane
    ell = np.minimum(ell, c.f(c.reach_px)) if np.isfinite(c.reach_px) else ell
    stopped_by_light = stopped_by_light & ~by_reach
    ell = np.where(np.isfinite(ell), ell, 0).astype(c.dtype, copy=False)
    return dict(lx=lx, ly=ly, lz=lz, nz=nz, ndl=ndl, x0=x0, y0=y0, z0=z0, delta=delta,
                h_rec=h_rec, ell=ell, ell_light=ell_light, stopped_by_light=stopped_by_light,
                by_reach=by_reach)


def _march_band(c, r, k_eff, occupancy, cancel):
    """March the rays of one band K steps and add the tangent-plane tail → t for the band."""
    f, d = c.f, c.d
    lx, ly, lz, ell = r["lx"], r["ly"], r["lz"], r["ell"]
    x0, y0, z0, delta, h_rec = r["x0"], r["y0"], r["z0"], r["delta"], r["h_rec"]
    inside = np.zeros(ell.shape, c.dtype)
    if k_eff:
        delta_start = delta
        a = ell / f(k_eff)
        ax, ay, az = a * lx, a * ly, a * lz
        # (each slope alone: a 2D image's lookups gather by flat index, about twice as fast)
        slope_x, slope_y = (None, None) if c.zs is not None else \
            (np.ascontiguousarray(c.slopes[..., i]) for i in (0, 1))
        for k in range(1, k_eff + 1):
            if cancel is not None and cancel():
                raise BakeCancelled()
            px = x0 + f(k) * ax
            py = y0 + f(k) * ay
            if c.zs is not None:
                h_here = sample_extend(c.zs, px, py)
            else:
                mx, my = px - f(0.5) * ax, py - f(0.5) * ay
                h_rec = h_rec + sample_extend(slope_x, mx, my) * ax + \
                    sample_extend(slope_y, mx, my) * ay
                h_here = h_rec
            new_delta = h_here - (z0 + f(k) * az)
            inside += occupancy_fraction(delta, new_delta, occupancy) * a
            delta = new_delta
        # A zero-length march (P0 already outside the box) learns nothing: keep δ0 for the tail.
        delta = np.where(ell > 0, delta, delta_start)

    # Tail: the march ended inside (image border, or K = 0): extrapolate along the tangent
    # plane of P_S, where δ falls at (N·L)/N.z per unit s. Never past a point light.
    ndl = r["ndl"]
    rate = ndl / r["nz"]
    with np.errstate(divide="ignore", invalid="ignore"):
        tail = np.where(rate > 0, delta / rate, np.inf)
        # stopped by the reach: the rest of the ray against the tangent plane itself
        plane = np.where(ndl > 0, np.maximum(d / ndl - ell, 0), np.inf)
    tail = np.where(delta > 0, tail, 0)
    tail = np.where(r["by_reach"], plane, tail)
    if r["ell_light"] is not None:
        tail = np.minimum(tail, r["ell_light"] - ell)
    tail = np.where(~r["stopped_by_light"], tail, 0)
    dist = inside + tail

    if d > 0:
        t = d / np.maximum(dist, d)
    else:
        # d → 0: max(N·L, 0) × hard visibility (nothing of the ray inside the relief).
        t = np.where(dist > f(1e-3), 0, np.maximum(ndl, 0))
    if c.light.kind == "sun" and c.light.vector[2] <= 0:
        t = np.zeros_like(t)
    t = np.where(np.isfinite(t), t, 0)
    return np.clip(t, 0, 1).astype(c.dtype, copy=False)
