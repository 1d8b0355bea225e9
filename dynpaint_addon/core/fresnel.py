"""Fresnel: physical (for the view ray) and the paper's art-directed piecewise-linear curve (§10).

Both take unit normals n (H, W, 3) (or any (..., 3)); cos θ = I·N = N.z, sin θ = |N.xy|.
"""
import numpy as np

from .warps import clamp_eta

DOMAINS = ("cos", "sin")


def fresnel_physical(n, eta):
    """§10 physical Fresnel for the view ray, unpolarized: F = (F_s + F_p)/2 with
    g = √(η² − sin²θ), F_s = ((cos θ − g)/(cos θ + g))², F_p = ((η²cos θ − g)/(η²cos θ + g))².
    F = 1 under total internal reflection (η² < sin²θ), never a NaN from the root.
    """
    dtype = n.dtype
    eta = dtype.type(clamp_eta(eta))
    e2 = eta * eta
    c = np.clip(n[..., 2], 0, 1)
    s2 = np.clip(n[..., 0] ** 2 + n[..., 1] ** 2, 0, 1)
    g2 = e2 - s2
    tir = g2 < 0
    g = np.sqrt(np.maximum(g2, 0))
    tiny = dtype.type(1e-30)
    fs = ((c - g) / np.maximum(c + g, tiny)) ** 2
    fp = ((e2 * c - g) / np.maximum(e2 * c + g, tiny)) ** 2
    f = np.clip(0.5 * (fs + fp), 0, 1)
    return np.where(tir, dtype.type(1), f).astype(dtype, copy=False)


def art_variable(n, domain):
    """The art-directed curve's abscissa: 0 at normal incidence, 1 at grazing.

    domain 'sin': x = sin θ = |N.xy|. domain 'cos': x = 1 − cos θ = 1 − N.z (the same two
    controls placed along cos θ, which fits the physical curve about twice as well, §10).
    """
    if domain == "sin":
        return np.clip(np.hypot(n[..., 0], n[..., 1]), 0, 1)
    if domain == "cos":
        return np.clip(1 - n[..., 2], 0, 1)
    raise ValueError(f"unknown Fresnel domain {domain!r} (expected one of {', '.join(DOMAINS)})")


def art_curve(x, x1, x2, kappa=0.0):
    """§10 piecewise-linear Fresnel of the abscissa x ∈ [0, 1].

    F = 0 for x ≤ x1 ("total refraction" point), linear to ½ at x2 ("equal mix" point), then
    linear to 1 at x = 1. x1 = x2 or x2 = 1 become steps. κ ∈ [−1, 1] runs from total refraction
    to total reflection: κ ≥ 0: F ← F + κ(1 − F); κ < 0: F ← (1 + κ)F.
    """
    x = np.asarray(x)
    dtype = x.dtype
    x1 = float(np.clip(x1, 0, 1))
    x2 = float(np.clip(x2, x1, 1))
    rise1 = 0.5 * (x - x1) / (x2 - x1) if x2 > x1 else np.full_like(x, 0.5)
    rise2 = 0.5 + 0.5 * (x - x2) / (1 - x2) if x2 < 1 else np.full_like(x, 1.0)
    f = np.where(x <= x1, 0, np.where(x <= x2, rise1, rise2))
    f = np.where(x >= 1, 1, f)
    kappa = float(np.clip(kappa, -1, 1))
    f = f + kappa * (1 - f) if kappa >= 0 else (1 + kappa) * f
    return np.clip(f, 0, 1).astype(dtype, copy=False)


def fresnel_art(n, x1, x2, kappa=0.0, domain="cos"):
    """§10 art-directed Fresnel of unit normals (see art_curve, art_variable)."""
    return art_curve(art_variable(n, domain), x1, x2, kappa)


def fit_art_fresnel(eta, domain="cos", samples=2001):
    """Best (x1, x2) for the art-directed curve against the physical one (minimax over θ).

    Returns (x1, x2, max_abs_error). A coarse-to-fine grid search: cheap, deterministic and
    enough to reproduce §10's figures (≈0.10 in sin θ, ≈0.057 in cos θ for η = 1.5).
    """
    theta = np.linspace(0, np.pi / 2, samples)
    n = np.stack([np.sin(theta), np.zeros_like(theta), np.cos(theta)], axis=-1)
    target = fresnel_physical(n, eta)
    x = art_variable(n, domain)
    best = (0.0, 0.0, np.inf)
    lo1, hi1, lo2, hi2 = 0.0, 1.0, 0.0, 1.0
    for _ in range(4):
        for a in np.linspace(lo1, hi1, 41):
            for b in np.linspace(max(a, lo2), hi2, 41):
                err = float(np.max(np.abs(art_curve(x, a, b) - target)))
                if err < best[2]:
                    best = (float(a), float(b), err)
        span1, span2 = (hi1 - lo1) / 10, (hi2 - lo2) / 10
        lo1, hi1 = max(0.0, best[0] - span1), min(1.0, best[0] + span1)
        lo2, hi2 = max(0.0, best[1] - span2), min(1.0, best[1] + span2)
    return best
