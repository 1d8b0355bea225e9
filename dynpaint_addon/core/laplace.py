"""Poisson solves on the pixel grid, numpy only (docs/shape-from-painting.md).

Two solvers for the graph Laplacian of the 4-neighbour pixel grid:

* `poisson_neumann` — the whole image with free (Neumann) edges, exactly, by the discrete
  cosine transform: the DCT-II basis diagonalises the Neumann second difference, eigenvalue
  2 cos(πk/N) − 2 per axis, so L z = f is one forward and one inverse 2-D DCT (O(n log n)).
* `solve` — any subset of the grid's edges (a cut mask) and pixels held at 0 beyond an edge
  (a `Grid`), by conjugate gradients preconditioned with a multigrid V-cycle whose coarse
  levels merge 2×2 blocks (`Multigrid`): a few tens of iterations at any size.

Both use the sign convention L z = Σ_neighbours (z_nb − z) (negative semi-definite) and
solve −L z = b, so b is a "source": −Δz = b.

    >>> z = poisson_neumann(np.zeros((4, 5)))
    >>> z.shape, float(abs(z).max())
    ((4, 5), 0.0)
"""
import hashlib
import threading
from collections import OrderedDict

import numpy as np



def _dct(x, axis):
    """Unnormalised DCT-II along `axis`: X_k = Σ_m x_m cos(πk(2m + 1)/(2N)) (Makhoul's FFT)."""
    x = np.moveaxis(x, axis, -1)
    n = x.shape[-1]
    v = np.concatenate([x[..., ::2], x[..., 1::2][..., ::-1]], axis=-1)
    twiddle = np.exp(-0.5j * np.pi * np.arange(n) / n)
    return np.moveaxis(np.real(np.fft.fft(v, axis=-1) * twiddle), -1, axis)


def _idct(X, axis):
    """Inverse of `_dct` (a scaled DCT-III)."""
    X = np.moveaxis(X, axis, -1)
    n = X.shape[-1]
    reversed_ = np.concatenate([np.zeros_like(X[..., :1]), X[..., :0:-1]], axis=-1)
    twiddle = np.exp(0.5j * np.pi * np.arange(n) / n)
    v = np.real(np.fft.ifft((X - 1j * reversed_) * twiddle, axis=-1))
    x = np.empty_like(v)
    half = (n + 1) // 2
    x[..., ::2] = v[..., :half]
    x[..., 1::2] = v[..., half:][..., ::-1]
    return np.moveaxis(x, -1, axis)


def poisson_neumann(b):
    """Solve −L z = b on the whole grid with free edges → z with mean 0 (b's mean is ignored:
    a Neumann problem is solvable only for sources that sum to 0, the rest is a constant)."""
    b = np.asarray(b, dtype=np.float64)
    h, w = b.shape
    eig = (2 - 2 * np.cos(np.pi * np.arange(h) / h))[:, None] + \
        (2 - 2 * np.cos(np.pi * np.arange(w) / w))[None, :]
    eig[0, 0] = 1.0
    coeff = _dct(_dct(b, 0), 1) / eig
    coeff[0, 0] = 0.0
    return _idct(_idct(coeff, 0), 1)


def edge_sums(ex, ey, out):
    """Add each edge's value to both pixels it joins (ex (H, W−1) between (i, j) and
    (i, j + 1), ey (H−1, W) between (i, j) and (i + 1, j)) into `out` (H, W) → out."""
    out[:, :-1] += ex
    out[:, 1:] += ex
    out[:-1, :] += ey
    out[1:, :] += ey
    return out


class Grid:
    """The operator A z = Σ_edges w_e (z_a − z_b) + d·z: −L over the kept edges (weights wx
    between (i, j) and (i, j + 1), wy between (i, j) and (i + 1, j)) plus a Dirichlet term d
    where a pixel's neighbour beyond an edge is held at 0. A pixel with no edge and no d is
    not an unknown (it stays 0). dtype float32 halves the time where ~1e-4 is enough.
    """

    def __init__(self, wx, wy, dirichlet=None, dtype=np.float64):
        self.dtype = np.dtype(dtype)
        self.wx, self.wy = np.asarray(wx, dtype), np.asarray(wy, dtype)
        h, w = self.wy.shape[0] + 1, self.wx.shape[1] + 1
        self.shape = (h, w)
        self.dirichlet = np.zeros((h, w), dtype) if dirichlet is None else \
            np.asarray(dirichlet, dtype)
        self.diag = diag = edge_sums(self.wx, self.wy, self.dirichlet.copy())
        self.free = diag > 0
        self.inv_diag = np.where(self.free, 1 / np.where(self.free, diag, 1), 0).astype(dtype)

    def dense(self):
        """The operator as an (n, n) matrix over the grid's pixels in row order: the diagonal,
        −w between neighbours (what `apply` gives each unit vector, exactly)."""
        h, w = self.shape
        a = np.diag(self.diag.ravel())
        i = np.arange(h * w).reshape(h, w)
        for weights, p, q in ((self.wx, i[:, :-1], i[:, 1:]), (self.wy, i[:-1], i[1:])):
            a[p.ravel(), q.ravel()] = a[q.ravel(), p.ravel()] = 0 - weights.ravel()   # (no −0)
        return a

    def apply(self, z):
        out = self.diag * z
        out[:, :-1] -= self.wx * z[:, 1:]
        out[:, 1:] -= self.wx * z[:, :-1]
        out[:-1, :] -= self.wy * z[1:, :]
        out[1:, :] -= self.wy * z[:-1, :]
        return out


def _coarse(grid):
    """The same operator on 2×2 blocks: Galerkin (Pᵀ A P) for P = "each block's pixels share
    one value", so weights across block sides add up, edges inside a block vanish and a cut
    stays a cut. Odd sizes are padded with a pixel that is no unknown."""
    h, w = grid.shape
    ph, pw = h % 2, w % 2
    wx = np.pad(grid.wx, ((0, ph), (0, pw)))
    wy = np.pad(grid.wy, ((0, ph), (0, pw)))
    d = np.pad(grid.dirichlet, ((0, ph), (0, pw)))
    h2, w2 = (h + ph) // 2, (w + pw) // 2
    wx_c = wx[:, 1::2][:, :w2 - 1].reshape(h2, 2, w2 - 1).sum(1)
    wy_c = wy[1::2, :][:h2 - 1].reshape(h2 - 1, w2, 2).sum(2)
    return Grid(wx_c, wy_c, d.reshape(h2, 2, w2, 2).sum((1, 3)), grid.dtype)


def _restrict(r, shape):
    h, w = r.shape
    r = np.pad(r, ((0, h % 2), (0, w % 2)))
    return r.reshape(shape[0], 2, shape[1], 2).sum((1, 3))


def _prolong(e, shape):
    h2, w2 = e.shape
    fine = np.broadcast_to(e[:, None, :, None], (h2, 2, w2, 2)).reshape(2 * h2, 2 * w2)
    return fine[:shape[0], :shape[1]]


def _coarsest_inverse(grid):
    """The (pseudo-)inverse of a small grid's operator (n ≤ 256 pixels, dense). Where every
    connected part of its unknowns holds a Dirichlet pixel, the operator on them is positive
    definite: their block's inverse, in place in an n × n zero matrix — the pseudo-inverse
    but for rounding, 4–6× cheaper at 200–256 unknowns (4 against 16 ms; a stroke's draft
    inflates a part at each dab). A part with none (free edges: heights up to a constant)
    is singular: the pseudo-inverse."""
    a = grid.dense().astype(np.float64)
    free = grid.free.ravel()
    labels, count = components(grid.wx > 0, grid.wy > 0)
    parts_of_unknowns = labels.ravel()[free]
    pinned = np.bincount(parts_of_unknowns, grid.dirichlet.ravel()[free] > 0, count) > 0
    if not free.any() or not pinned[parts_of_unknowns].all():
        return np.linalg.pinv(a, hermitian=True)
    out = np.zeros_like(a)
    out[np.ix_(free, free)] = np.linalg.inv(a[np.ix_(free, free)])
    return out


class Multigrid:
    """A V-cycle for a Grid: damped Jacobi smoothing, block (aggregation) coarse levels down to
    ≤ 256 pixels solved by a (pseudo-)inverse. Symmetric, so it preconditions CG (`solve`)."""

    SMOOTH, OMEGA, OVERCORRECT = 2, 0.8, 1.8

    def __init__(self, grid):
        self.levels = [grid]
        while self.levels[-1].shape[0] * self.levels[-1].shape[1] > 256:
            self.levels.append(_coarse(self.levels[-1]))
        self.coarsest = _coarsest_inverse(self.levels[-1])

    def __call__(self, r, level=0):
        grid = self.levels[level]
        if level == len(self.levels) - 1:
            return (self.coarsest @ r.ravel()).reshape(r.shape).astype(grid.dtype)
        scaled = self.OMEGA * grid.inv_diag
        e = scaled * r
        for _ in range(self.SMOOTH - 1):
            e += scaled * (r - grid.apply(e))
        coarse = self.levels[level + 1]
        e += self.OVERCORRECT * _prolong(self(_restrict(r - grid.apply(e), coarse.shape),
                                              level + 1), r.shape)
        for _ in range(self.SMOOTH):
            e += scaled * (r - grid.apply(e))
        return e


def solve(grid, b, tol=1e-4, max_iter=200):
    """grid.apply(z) = b by multigrid-preconditioned conjugate gradients → (z float64,
    iterations, relative residual). Consistent singular systems (free edges) converge too;
    b is taken as 0 where the grid has no unknown."""
    mg = Multigrid(grid)
    dt = grid.dtype.type
    b = np.where(grid.free, b, 0).astype(dt)
    z = np.zeros(grid.shape, dt)
    r = b.copy()
    norm_b = float(np.sqrt(np.sum(b.astype(np.float64) ** 2))) or 1.0
    zr = mg(r)
    p = zr.copy()
    rz = float(np.sum(r * zr, dtype=np.float64))
    it, res = 0, float(np.sqrt(np.sum(r.astype(np.float64) ** 2))) / norm_b
    while it < max_iter and res > tol:
        ap = grid.apply(p)
        pap = float(np.sum(p * ap, dtype=np.float64))
        if pap <= 0:
            break
        alpha = rz / pap
        z += dt(alpha) * p
        r -= dt(alpha) * ap
        zr = mg(r)
        rz_new = float(np.sum(r * zr, dtype=np.float64))
        p = zr + dt(rz_new / rz) * p
        rz = rz_new
        it += 1
        res = float(np.sqrt(np.sum(r.astype(np.float64) ** 2))) / norm_b
    return z.astype(np.float64), it, res


def components(wx, wy):
    """Connected parts of the pixel grid joined by the edges wx (H, W−1), wy (H−1, W) (bool)
    → (labels (H, W) in 0 … count − 1, count): runs of each row, merged along wy by
    min-label propagation with pointer jumping."""
    h, w = wx.shape[0], wx.shape[1] + 1
    start = np.ones((h, w), bool)
    start[:, 1:] = ~wx
    run = np.cumsum(start.ravel()).reshape(h, w) - 1
    a, b = run[:-1][wy], run[1:][wy]
    # two runs that touch along many columns are one edge: in row order their pairs repeat
    # one after another (both runs' indices only grow along a row)
    new = np.ones(a.shape, bool)
    new[1:] = (a[1:] != a[:-1]) | (b[1:] != b[:-1])
    dense, count = graph_parts(int(run[-1, -1]) + 1, a[new], b[new])
    return dense[run], count


def graph_parts(n, a, b):
    """Connected parts of a graph of n nodes with edges a[i]–b[i] → (labels in 0 … count − 1,
    count; parts numbered in the order of their first node), by min-label propagation with
    pointer jumping over the nodes that have an edge (the others are parts of their own)."""
    label = np.arange(n)
    nodes, ends = np.unique(np.concatenate([a, b]), return_inverse=True)
    least = np.arange(len(nodes))                      # each node's least node joined to it
    a, b = ends[:len(a)], ends[len(a):]
    while True:
        low = np.minimum(least[a], least[b])
        new = least.copy()
        np.minimum.at(new, a, low)
        np.minimum.at(new, b, low)
        new = new[new]
        if np.array_equal(new, least):
            break
        least = new
    label[nodes] = nodes[least]
    first = label == np.arange(n)                      # each part's least node
    return (np.cumsum(first) - 1)[label], int(first.sum())


def parts(labels, count, where):
    """(label, its bounding box (r0, r1, c0, c1)) of each label with a pixel where `where`
    (H, W bool) holds, in label order."""
    h, w = labels.shape
    flat = labels.ravel()
    kept = np.bincount(flat, where.ravel(), count) > 0
    # (only the kept labels' pixels: a figure is a part of the image, and ufunc.at is slow)
    at = np.flatnonzero(kept[flat])
    flat, (rows, cols) = flat[at], np.divmod(at, w)
    box = np.zeros((count, 4), np.int64)
    box[:, 0], box[:, 2] = h, w
    np.minimum.at(box[:, 0], flat, rows)
    np.maximum.at(box[:, 1], flat, rows + 1)
    np.minimum.at(box[:, 2], flat, cols)
    np.maximum.at(box[:, 3], flat, cols + 1)
    return [(int(k), tuple(box[k])) for k in np.flatnonzero(kept)]


_SOLVED = OrderedDict()    # a part's digest → (its z, iterations, residual), newest last
_SOLVED_LOCK = threading.Lock()    # (a lit drawing's redraw inflates in a worker thread)
SOLVED_BYTES = 64 << 20    # what the parts kept may hold; a part over a quarter of it is not
                           # kept (nor hashed: a large image's solve is not a stroke's)


def _digest(*arrays):
    h = hashlib.blake2b(digest_size=16)
    for a in arrays:
        h.update(repr((a.shape, a.dtype.str)).encode())
        h.update(np.ascontiguousarray(a).data)
    return h.digest()


def _solved(part, bk, tol):
    """`solve` of one part, kept by its digest: a stroke re-solves the parts it touched only
    (the others' heights are theirs, bit for bit: solve_parts)."""
    if 4 * bk.size * 8 > SOLVED_BYTES:
        return solve(part, bk, tol)
    key = _digest(part.wx, part.wy, part.dirichlet, bk, np.array(tol))
    with _SOLVED_LOCK:
        if key in _SOLVED:
            _SOLVED.move_to_end(key)
            return _SOLVED[key]
    found = solve(part, bk, tol)
    with _SOLVED_LOCK:
        _SOLVED[key] = found
        while sum(z.nbytes for z, _, _ in _SOLVED.values()) > SOLVED_BYTES:
            _SOLVED.popitem(last=False)
    return found


def forget_solved_parts():
    """Drop the parts kept (their heights are the same when solved again: memory only)."""
    with _SOLVED_LOCK:
        _SOLVED.clear()


def solve_parts(grid, b, labels, count, tol=1e-4):
    """`solve` on each connected part of the grid alone, in its own bounding box → (z, most
    iterations, largest relative residual). A part's heights depend on its own pixels only:
    the same drawing gives the same heights, bit for bit, wherever it lies and whatever else
    in the image changes (a painting's frames, pipeline.md §16) — so the parts solved lately
    are kept and a part met again is not solved again. labels: (H, W) in 0 … count − 1, no
    grid edge joining two labels (`components` of the grid's edges)."""
    z = np.zeros(grid.shape)
    most, worst = 0, 0.0
    for k, (r0, r1, c0, c1) in parts(labels, count, grid.free):
        own = labels[r0:r1, c0:c1] == k
        part = Grid(grid.wx[r0:r1, c0:c1 - 1] * (own[:, 1:] & own[:, :-1]),
                    grid.wy[r0:r1 - 1, c0:c1] * (own[1:] & own[:-1]),
                    grid.dirichlet[r0:r1, c0:c1] * own, grid.dtype)
        bk = np.where(own, b[r0:r1, c0:c1], 0)
        if not bk.any():                   # no source (a flat background): z = 0 exactly
            continue
        zk, iterations, residual = _solved(part, bk, tol)
        z[r0:r1, c0:c1] = np.where(own, zk, z[r0:r1, c0:c1])
        most, worst = max(most, iterations), max(worst, residual)
    return z, most, worst
