"""The natural-map error of softpack's 3D answers, recomputed independently.

Reads each problem of ../shared/data/fclib3d with its own parser (numpy,
h5py, scipy; no line of softpack's readers), the reactions that
``softpack-fclib --dim 3 --solution-out DIR`` wrote (DIR/NAME.r.csv), and
prints the error of docs/contact_3d.md:

    u = W r + q,  u~ = (u_n + mu |u_t|, u_t),
    e = ||r - proj_K(r - u~)|| / max(||r||, ||u||, ||q||)

A global problem (M v = H r + f, u = H^T v + w) is condensed here with a
dense solve of M: W = H^T M^-1 H, q = H^T M^-1 f + w.

    /usr/bin/python3 bench/contact/fclib3d_check.py DIR FILE...
"""

import pathlib
import sys

import h5py
import numpy as np
import scipy.sparse as sp


def read_dat(path):
    """W, q, mu of a Siconos text problem (storage 0 dense, 1 blocks)."""
    tok = iter(pathlib.Path(path).read_text().split())
    nxt = lambda: float(next(tok))  # noqa: E731
    d, nc = int(nxt()), int(nxt())
    storage, n, _ = int(nxt()), int(nxt()), int(nxt())
    W = np.zeros((n, n))
    if storage == 0:
        nxt(), nxt()
        W = np.array([nxt() for _ in range(n * n)]).reshape(n, n).T
    elif storage == 1:
        nb, br, bc = int(nxt()), int(nxt()), int(nxt())
        rows = [int(nxt()) for _ in range(br)]
        [int(nxt()) for _ in range(bc)]
        f1, f2 = int(nxt()), int(nxt())
        start = [int(nxt()) for _ in range(f1)]
        col = [int(nxt()) for _ in range(f2)]
        for a in range(br):
            for k in range(start[a], start[a + 1]):
                nxt()
                b = col[k]
                blk = np.array([nxt() for _ in range(d * d)]).reshape(d, d).T
                W[d * a:d * a + d, d * b:d * b + d] += blk
        assert rows[-1] == n and nb == f2
    else:
        raise SystemExit(f"{path}: storage {storage} not read")
    q = np.array([nxt() for _ in range(n)])
    mu = np.array([nxt() for _ in range(nc)])
    return W, q, mu


def csparse(group):
    m, n, nz = (int(group[k][()][0]) for k in ("m", "n", "nz"))
    p, i, x = group["p"][()], group["i"][()], group["x"][()]
    if nz == -2:
        return sp.csr_matrix((x[:p[-1]], i[:p[-1]], p), shape=(m, n))
    if nz == -1:
        return sp.csc_matrix((x[:p[-1]], i[:p[-1]], p), shape=(m, n))
    return sp.coo_matrix((x[:nz], (i[:nz], p[:nz])), shape=(m, n))


def read_hdf5(path):
    """W, q, mu of an FCLIB file, local or global (condensed)."""
    with h5py.File(path) as f:
        if "fclib_local" in f:
            g = f["fclib_local"]
            return (csparse(g["W"]).toarray(), g["vectors/q"][()],
                    g["vectors/mu"][()])
        g = f["fclib_global"]
        M = csparse(g["M"]).toarray()
        H = csparse(g["H"]).toarray()
        f_, w = g["vectors/f"][()], g["vectors/w"][()]
        W = H.T @ np.linalg.solve(M, H)
        q = H.T @ np.linalg.solve(M, f_) + w
        return W, q, g["vectors/mu"][()]


def proj_cone(x, mu):
    """Projection on {|x_t| <= mu x_n}, row by row."""
    xn, xt = x[:, 0], x[:, 1:]
    nt = np.linalg.norm(xt, axis=1)
    out = x.copy()
    polar = mu * nt <= -xn
    inside = nt <= mu * xn
    edge = ~(polar | inside)
    pn = (xn[edge] + mu[edge] * nt[edge]) / (1 + mu[edge] ** 2)
    out[edge, 0] = pn
    out[edge, 1:] = (mu[edge] * pn / nt[edge])[:, None] * xt[edge]
    out[polar] = 0
    return out


def error(W, q, mu, r):
    u = W @ r + q
    R, U = r.reshape(-1, 3), u.reshape(-1, 3)
    ut = U.copy()
    ut[:, 0] += mu * np.linalg.norm(U[:, 1:], axis=1)
    res = np.linalg.norm(R - proj_cone(R - ut, mu))
    scale = max(np.linalg.norm(r), np.linalg.norm(u), np.linalg.norm(q))
    return res / scale if scale > np.finfo(float).eps else res


def main():
    out = pathlib.Path(sys.argv[1])
    for name in sys.argv[2:]:
        path = pathlib.Path(name)
        W, q, mu = read_dat(path) if path.suffix == ".dat" else read_hdf5(path)
        r = np.loadtxt(out / f"{path.stem}.r.csv")  # softpack-fclib's name
        print(f"{path.name}: contacts {mu.size}, error {error(W, q, mu, r):.3e}")


if __name__ == "__main__":
    main()
