//! Reference implementation of the quaternion deformation (Samareh), written naively in `f64`
//! with `Vec` and rotation matrices, sharing no code with the kernel.
//!
//! Differences in formulation, so the two check each other:
//! - node normals loop over every element for every node (`O(B · E)`), and face normals use
//!   Newell's polygon formula rather than cross products of diagonals;
//! - 2D edge rotations are differences of two `atan2` direction angles wrapped into
//!   `(−π, π]` (the kernel uses one `atan2` of cross and dot);
//! - 3D rotations are rotation *matrices*: `R1` by Rodrigues' formula from the axis
//!   `n_u × n_d` and the angle `acos(n_u · n_d)` (the paper's literal construction), the twist
//!   as a matrix about `n_d`, `R = R2 R1`;
//! - inverse-distance weights are the textbook `d^−p`; quaternions are averaged as 4-vectors;
//! - TFI is the written-out boolean sum (2D: four sides and four corners; 3D: six faces, twelve
//!   edges, eight corners).

/// A 3×3 matrix, row major.
pub type Mat3 = [[f64; 3]; 3];

fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm3(a: [f64; 3]) -> f64 {
    dot3(a, a).sqrt()
}
fn scale3(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `M v`.
pub fn mat_vec(m: &Mat3, v: [f64; 3]) -> [f64; 3] {
    [dot3(m[0], v), dot3(m[1], v), dot3(m[2], v)]
}

/// `A B`.
pub fn mat_mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut r = [[0.0; 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    r
}

/// Rotation matrix about the unit axis `u` by `angle` (Rodrigues).
pub fn axis_angle_matrix(u: [f64; 3], angle: f64) -> Mat3 {
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    let [x, y, z] = u;
    [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]
}

/// Rotation matrix of the unit quaternion `[w, x, y, z]` (computed as `q v q*` column by
/// column with the Hamilton product written out).
pub fn quat_matrix(q: [f64; 4]) -> Mat3 {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let q = [q[0] / n, q[1] / n, q[2] / n, q[3] / n];
    let mul = |a: [f64; 4], b: [f64; 4]| -> [f64; 4] {
        [
            a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
            a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
            a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
            a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
        ]
    };
    let conj = [q[0], -q[1], -q[2], -q[3]];
    let mut m = [[0.0; 3]; 3];
    for col in 0..3 {
        let mut e = [0.0; 4];
        e[col + 1] = 1.0;
        let r = mul(mul(q, e), conj);
        for row in 0..3 {
            m[row][col] = r[row + 1];
        }
    }
    m
}

/// Largest absolute entry difference of two matrices.
pub fn mat_diff(a: &Mat3, b: &Mat3) -> f64 {
    let mut d: f64 = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            d = d.max((a[i][j] - b[i][j]).abs());
        }
    }
    d
}

/// A boundary element: VTK kind code and nodes (boundary-local indices).
pub type Element = (u8, Vec<usize>);

/// Raw element normal in 3D (2D points have `z = 0`): `(t_y, −t_x, 0)` for a segment, Newell's
/// polygon normal (twice the area vector) for a triangle or quadrilateral.
pub fn element_normal(points: &[[f64; 3]], e: &Element) -> [f64; 3] {
    let p: Vec<[f64; 3]> = e.1.iter().map(|&i| points[i]).collect();
    if e.0 == 3 {
        let t = sub3(p[1], p[0]);
        return [t[1], -t[0], 0.0];
    }
    let mut n = [0.0; 3];
    for k in 0..p.len() {
        let a = p[k];
        let b = p[(k + 1) % p.len()];
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    n
}

/// Unit area-weighted node normals; `None` where the sum vanishes or the node is in no element.
pub fn node_normals(points: &[[f64; 3]], elements: &[Element]) -> Vec<Option<[f64; 3]>> {
    (0..points.len())
        .map(|i| {
            let mut s = [0.0; 3];
            let mut used = false;
            for e in elements {
                if e.1.contains(&i) {
                    used = true;
                    s = add3(s, element_normal(points, e));
                }
            }
            let l = norm3(s);
            if used && l > 1e-300 {
                Some(scale3(s, 1.0 / l))
            } else {
                None
            }
        })
        .collect()
}

fn wrap(a: f64) -> f64 {
    let mut a = a;
    while a > std::f64::consts::PI {
        a -= 2.0 * std::f64::consts::PI;
    }
    while a <= -std::f64::consts::PI {
        a += 2.0 * std::f64::consts::PI;
    }
    a
}

/// 2D node rotation angles: each segment turns by the wrapped change of its direction angle;
/// a node averages its segments' angles unwrapped to within π of the first (in element order).
pub fn rotation_angles_2d(u: &[[f64; 2]], d: &[[f64; 2]], segments: &[[usize; 2]]) -> Vec<f64> {
    (0..u.len())
        .map(|i| {
            let mut first: Option<f64> = None;
            let mut sum = 0.0;
            let mut n = 0.0;
            for s in segments {
                if s[0] != i && s[1] != i {
                    continue;
                }
                let au = (u[s[1]][1] - u[s[0]][1]).atan2(u[s[1]][0] - u[s[0]][0]);
                let ad = (d[s[1]][1] - d[s[0]][1]).atan2(d[s[1]][0] - d[s[0]][0]);
                let mut a = wrap(ad - au);
                match first {
                    None => first = Some(a),
                    Some(f) => {
                        if a - f > std::f64::consts::PI {
                            a -= 2.0 * std::f64::consts::PI;
                        } else if a - f < -std::f64::consts::PI {
                            a += 2.0 * std::f64::consts::PI;
                        }
                    }
                }
                sum += a;
                n += 1.0;
            }
            sum / n
        })
        .collect()
}

/// Edges of a boundary element (perimeter, in node order).
fn element_edges(e: &Element) -> Vec<[usize; 2]> {
    let n = e.1.len();
    if n == 2 {
        return vec![[e.1[0], e.1[1]]];
    }
    (0..n).map(|k| [e.1[k], e.1[(k + 1) % n]]).collect()
}

/// 3D node rotation matrices `R = R2 R1` (Samareh steps 2–3): `R1` turns `n_u` onto `n_d`
/// about `n_u × n_d` by `acos(n_u · n_d)`; `R2` twists about `n_d` by the circular mean of the
/// angles between the `R1`-rotated and the deformed neighbour edges projected on the deformed
/// tangent plane (one term per element edge at the node), each weighted by the product of the
/// two projected lengths.
pub fn rotations_3d(u: &[[f64; 3]], d: &[[f64; 3]], elements: &[Element]) -> Vec<Mat3> {
    let nu = node_normals(u, elements);
    let nd = node_normals(d, elements);
    (0..u.len())
        .map(|i| {
            let a = nu[i].expect("undeformed normal");
            let b = nd[i].expect("deformed normal");
            let axis = cross3(a, b);
            let l = norm3(axis);
            let angle = dot3(a, b).clamp(-1.0, 1.0).acos();
            let r1 = if l > 1e-300 {
                axis_angle_matrix(scale3(axis, 1.0 / l), angle)
            } else if dot3(a, b) > 0.0 {
                axis_angle_matrix([1.0, 0.0, 0.0], 0.0)
            } else {
                // Antiparallel: any axis orthogonal to a.
                let t = if a[0].abs() < 0.9 {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 1.0, 0.0]
                };
                let o = cross3(a, t);
                axis_angle_matrix(scale3(o, 1.0 / norm3(o)), std::f64::consts::PI)
            };
            let (mut ss, mut cc) = (0.0, 0.0);
            for e in elements {
                for [p, q] in element_edges(e) {
                    let j = if p == i {
                        q
                    } else if q == i {
                        p
                    } else {
                        continue;
                    };
                    let eu = mat_vec(&r1, sub3(u[j], u[i]));
                    let ed = sub3(d[j], d[i]);
                    let pu = sub3(eu, scale3(b, dot3(eu, b)));
                    let pd = sub3(ed, scale3(b, dot3(ed, b)));
                    // Weighted by the product of the projected lengths.
                    let ang = dot3(cross3(pu, pd), b).atan2(dot3(pu, pd));
                    let w = norm3(pu) * norm3(pd);
                    ss += w * ang.sin();
                    cc += w * ang.cos();
                }
            }
            let theta = ss.atan2(cc);
            mat_mul(&axis_angle_matrix(b, theta), &r1)
        })
        .collect()
}

/// `Δ = (d − o) − R (u − o)`.
pub fn translation(o: [f64; 3], u: [f64; 3], d: [f64; 3], r: &Mat3) -> [f64; 3] {
    sub3(sub3(d, o), mat_vec(r, sub3(u, o)))
}

/// `o + Δ + R (x − o)`.
pub fn apply(o: [f64; 3], x: [f64; 3], delta: [f64; 3], r: &Mat3) -> [f64; 3] {
    add3(add3(o, delta), mat_vec(r, sub3(x, o)))
}

/// Inverse-distance weighting with the textbook weights `|x − b_k|^−p`: returns, per point,
/// the weighted mean translation and the normalised weighted sum of the quaternions, each
/// flipped to the hemisphere of the nearest boundary node's quaternion. Boundary points
/// (listed in `boundary`) keep their values; a point at zero distance copies the nearest.
pub fn idw(
    points: &[[f64; 3]],
    boundary: &[usize],
    delta: &[[f64; 3]],
    quats: &[[f64; 4]],
    p: f64,
) -> (Vec<[f64; 3]>, Vec<[f64; 4]>) {
    let mut out_d = Vec::new();
    let mut out_q = Vec::new();
    for (i, x) in points.iter().enumerate() {
        if let Some(k) = boundary.iter().position(|&b| b == i) {
            out_d.push(delta[k]);
            out_q.push(quats[k]);
            continue;
        }
        let dist: Vec<f64> = boundary
            .iter()
            .map(|&b| norm3(sub3(*x, points[b])))
            .collect();
        let (kmin, dmin) =
            dist.iter().enumerate().fold(
                (0, f64::INFINITY),
                |(k, m), (j, &v)| if v < m { (j, v) } else { (k, m) },
            );
        if dmin == 0.0 {
            out_d.push(delta[kmin]);
            out_q.push(quats[kmin]);
            continue;
        }
        let refq = quats[kmin];
        let mut sd = [0.0; 3];
        let mut sq = [0.0; 4];
        let mut sw = 0.0;
        for k in 0..boundary.len() {
            let w = dist[k].powf(-p);
            sd = add3(sd, scale3(delta[k], w));
            let q = quats[k];
            let s = if (0..4).map(|c| q[c] * refq[c]).sum::<f64>() < 0.0 {
                -1.0
            } else {
                1.0
            };
            for c in 0..4 {
                sq[c] += w * s * q[c];
            }
            sw += w;
        }
        out_d.push(scale3(sd, 1.0 / sw));
        let n = (sq.iter().map(|c| c * c).sum::<f64>()).sqrt();
        out_q.push([sq[0] / n, sq[1] / n, sq[2] / n, sq[3] / n]);
    }
    (out_d, out_q)
}

/// Normalised arclength along grid lines: `s[p]` along direction `dir` of a block with dims
/// `[ni, nj, nk]` (i fastest). Uniform where a line has zero length.
pub fn arclength(points: &[[f64; 3]], dims: [usize; 3], dir: usize) -> Vec<f64> {
    let idx = |c: [usize; 3]| c[0] + dims[0] * (c[1] + dims[1] * c[2]);
    let mut s = vec![0.0; points.len()];
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                let c = [i, j, k];
                if c[dir] != 0 {
                    continue;
                }
                let line: Vec<usize> = (0..dims[dir])
                    .map(|m| {
                        let mut q = c;
                        q[dir] = m;
                        idx(q)
                    })
                    .collect();
                let mut cum = vec![0.0];
                for w in line.windows(2) {
                    let l = norm3(sub3(points[w[1]], points[w[0]]));
                    cum.push(cum.last().copied().unwrap_or(0.0) + l);
                }
                let total = *cum.last().unwrap_or(&0.0);
                for (m, &p) in line.iter().enumerate() {
                    s[p] = if total > 0.0 {
                        cum[m] / total
                    } else {
                        m as f64 / (dims[dir] - 1) as f64
                    };
                }
            }
        }
    }
    s
}

/// 2D TFI (all four sides given) of an `m`-component field with Soni arclength blending,
/// written out: `U + V − UV`. Interior values are replaced; sides are kept.
pub fn tfi_2d(points: &[[f64; 3]], ni: usize, nj: usize, f: &mut [Vec<f64>]) {
    let dims = [ni, nj, 1];
    let s = arclength(points, dims, 0);
    let t = arclength(points, dims, 1);
    let id = |i: usize, j: usize| i + ni * j;
    let m = f[0].len();
    for j in 1..nj - 1 {
        for i in 1..ni - 1 {
            let p = id(i, j);
            let (a, b) = (s[p], t[p]);
            let mut v = vec![0.0; m];
            for c in 0..m {
                let u = (1.0 - a) * f[id(0, j)][c] + a * f[id(ni - 1, j)][c];
                let w = (1.0 - b) * f[id(i, 0)][c] + b * f[id(i, nj - 1)][c];
                let uw = (1.0 - a) * (1.0 - b) * f[id(0, 0)][c]
                    + a * (1.0 - b) * f[id(ni - 1, 0)][c]
                    + (1.0 - a) * b * f[id(0, nj - 1)][c]
                    + a * b * f[id(ni - 1, nj - 1)][c];
                v[c] = u + w - uw;
            }
            f[p] = v;
        }
    }
}

/// 2D TFI along `j` only (lines from `j = 0` to `j = nj − 1`), as for O-grids.
pub fn tfi_2d_j(points: &[[f64; 3]], ni: usize, nj: usize, f: &mut [Vec<f64>]) {
    let t = arclength(points, [ni, nj, 1], 1);
    let m = f[0].len();
    for j in 1..nj - 1 {
        for i in 0..ni {
            let p = i + ni * j;
            let b = t[p];
            let v: Vec<f64> = (0..m)
                .map(|c| (1.0 - b) * f[i][c] + b * f[i + ni * (nj - 1)][c])
                .collect();
            f[p] = v;
        }
    }
}

/// 3D TFI (all six faces given), written out: faces − edges + corners.
pub fn tfi_3d(points: &[[f64; 3]], dims: [usize; 3], f: &mut [Vec<f64>]) {
    let [ni, nj, nk] = dims;
    let s = arclength(points, dims, 0);
    let t = arclength(points, dims, 1);
    let r = arclength(points, dims, 2);
    let id = |i: usize, j: usize, k: usize| i + ni * (j + nj * k);
    let m = f[0].len();
    let (i1, j1, k1) = (ni - 1, nj - 1, nk - 1);
    for k in 1..nk - 1 {
        for j in 1..nj - 1 {
            for i in 1..ni - 1 {
                let p = id(i, j, k);
                let (a, b, c) = (s[p], t[p], r[p]);
                let (a0, b0, c0) = (1.0 - a, 1.0 - b, 1.0 - c);
                let mut v = vec![0.0; m];
                for x in 0..m {
                    let g = |i: usize, j: usize, k: usize| f[id(i, j, k)][x];
                    let faces = a0 * g(0, j, k)
                        + a * g(i1, j, k)
                        + b0 * g(i, 0, k)
                        + b * g(i, j1, k)
                        + c0 * g(i, j, 0)
                        + c * g(i, j, k1);
                    let edges = a0 * b0 * g(0, 0, k)
                        + a * b0 * g(i1, 0, k)
                        + a0 * b * g(0, j1, k)
                        + a * b * g(i1, j1, k)
                        + a0 * c0 * g(0, j, 0)
                        + a * c0 * g(i1, j, 0)
                        + a0 * c * g(0, j, k1)
                        + a * c * g(i1, j, k1)
                        + b0 * c0 * g(i, 0, 0)
                        + b * c0 * g(i, j1, 0)
                        + b0 * c * g(i, 0, k1)
                        + b * c * g(i, j1, k1);
                    let corners = a0 * b0 * c0 * g(0, 0, 0)
                        + a * b0 * c0 * g(i1, 0, 0)
                        + a0 * b * c0 * g(0, j1, 0)
                        + a * b * c0 * g(i1, j1, 0)
                        + a0 * b0 * c * g(0, 0, k1)
                        + a * b0 * c * g(i1, 0, k1)
                        + a0 * b * c * g(0, j1, k1)
                        + a * b * c * g(i1, j1, k1);
                    v[x] = faces - edges + corners;
                }
                f[p] = v;
            }
        }
    }
}
