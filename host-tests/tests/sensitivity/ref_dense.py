"""Dense reference for the mesh sensitivities (numpy): the Jacobian J of the deformation
with respect to the boundary displacement, built explicitly, applied to v (tangent) and
transposed to w (adjoint).

Modes (input file as written by common.rs):
  springs  n D V m / points / edges (i j) / fixed / v / w: Batina stiffness 1/|e|, the
           graph Laplacian K; per component x_f = -K_ff^{-1} K_fb x_b.
  angle    n D V m eps / as springs: the angle-inclusion blocks k (d d^T/|d|^2 + eps I),
           k = 1/|d|, assembled over node-major dofs (V = D).
  matrix   n V / dense K (n V square, node-major) / fixed / v / w: x_f = -K_ff^{-1} K_fb x_b.
  idw      n D B p / points / boundary / v / w: x_i = sum_k w_ik x_k / sum_k w_ik with
           w_ik = |x_i - x_k|^-p (boundary nodes keep their own value).
Output: J v (n rows of V or D) then J^T w (n rows, zero at free nodes).
"""
import sys

import numpy as np


def read(path):
    with open(path) as f:
        return [line.split() for line in f if line.strip()]


def dirichlet_jacobian(K, fixed_dof):
    """J (all dofs x fixed dofs) of x_f = -K_ff^-1 K_fb x_b, x_b = x_b."""
    f = ~fixed_dof
    N = K.shape[0]
    J = np.zeros((N, fixed_dof.sum()))
    J[np.where(fixed_dof)[0], np.arange(fixed_dof.sum())] = 1.0
    J[f] = -np.linalg.solve(K[np.ix_(f, f)], K[np.ix_(f, fixed_dof)])
    return J


def apply(J, fixed_dof, v, w):
    jv = J @ v[fixed_dof]
    g = np.zeros_like(w)
    g[fixed_dof] = J.T @ w
    return jv, g


def springs(rows):
    n, D, V, m = (int(x) for x in rows[0])
    pts = np.array(rows[1:1 + n], float)
    edges = np.array(rows[1 + n:1 + n + m], int)
    at = 1 + n + m
    fixed = np.array([int(r[0]) != 0 for r in rows[at:at + n]])
    v = np.array(rows[at + n:at + 2 * n], float)
    w = np.array(rows[at + 2 * n:at + 3 * n], float)
    K = np.zeros((n, n))
    for i, j in edges:
        k = 1.0 / np.linalg.norm(pts[i] - pts[j])
        K[i, j] -= k
        K[j, i] -= k
        K[i, i] += k
        K[j, j] += k
    J = dirichlet_jacobian(K, fixed)
    out = [apply(J, fixed, v[:, c], w[:, c]) for c in range(V)]
    return np.stack([o[0] for o in out], 1), np.stack([o[1] for o in out], 1)


def angle(rows):
    n, D, V, m = (int(x) for x in rows[0][:4])
    eps = float(rows[0][4])
    pts = np.array(rows[1:1 + n], float)
    edges = np.array(rows[1 + n:1 + n + m], int)
    at = 1 + n + m
    fixed = np.repeat(np.array([int(r[0]) != 0 for r in rows[at:at + n]]), D)
    v = np.array(rows[at + n:at + 2 * n], float).reshape(-1)
    w = np.array(rows[at + 2 * n:at + 3 * n], float).reshape(-1)
    K = np.zeros((n * D, n * D))
    for i, j in edges:
        d = pts[j] - pts[i]
        k = 1.0 / np.linalg.norm(d)
        B = k * (np.outer(d, d) / d.dot(d) + eps * np.eye(D))
        si, sj = slice(i * D, i * D + D), slice(j * D, j * D + D)
        K[si, si] += B
        K[sj, sj] += B
        K[si, sj] -= B
        K[sj, si] -= B
    J = dirichlet_jacobian(K, fixed)
    jv, g = apply(J, fixed, v, w)
    return jv.reshape(n, D), g.reshape(n, D)


def matrix(rows):
    n, V = (int(x) for x in rows[0])
    K = np.array(rows[1:1 + n * V], float)
    at = 1 + n * V
    fixed = np.repeat(np.array([int(r[0]) != 0 for r in rows[at:at + n]]), V)
    v = np.array(rows[at + n:at + 2 * n], float).reshape(-1)
    w = np.array(rows[at + 2 * n:at + 3 * n], float).reshape(-1)
    J = dirichlet_jacobian(K, fixed)
    jv, g = apply(J, fixed, v, w)
    return jv.reshape(n, V), g.reshape(n, V)


def idw(rows):
    n, D, B = (int(x) for x in rows[0][:3])
    p = float(rows[0][3])
    pts = np.array(rows[1:1 + n], float)
    bnd = np.array([int(r[0]) for r in rows[1 + n:1 + n + B]])
    at = 1 + n + B
    v = np.array(rows[at:at + n], float)
    w = np.array(rows[at + n:at + 2 * n], float)
    J = np.zeros((n, n))  # node to node; columns of boundary nodes only
    is_b = np.zeros(n, bool)
    is_b[bnd] = True
    for i in range(n):
        if is_b[i]:
            J[i, i] = 1.0
            continue
        d = np.linalg.norm(pts[i] - pts[bnd], axis=1)
        if np.any(d == 0.0):
            J[i, bnd[np.argmax(d == 0.0)]] = 1.0
            continue
        wt = d ** -p
        np.add.at(J[i], bnd, wt / wt.sum())
    jv = J @ v
    g = J.T @ w
    g[~is_b] = 0.0
    return jv, g


def main():
    mode, path = sys.argv[1], sys.argv[2]
    jv, g = {"springs": springs, "angle": angle, "matrix": matrix, "idw": idw}[mode](read(path))
    for r in np.vstack([jv, g]):
        print(" ".join(repr(float(x)) for x in r))


if __name__ == "__main__":
    main()
