//! Target 13: the stiffness choices and the reach control on arbitrary small 2D point sets and
//! graphs (random edges, symmetrised), wall lists, exponents, factors, distances, radii and
//! rotations (NaN, negative, zero and huge values included): never panics; an error leaves
//! every output bit-identical; on success scaled stiffness is finite, positive and exactly
//! symmetric, factors are finite and positive, reach-limited translations are never longer
//! than before and nodes at or beyond the radius get no motion.
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::quaternion::limit_reach;
use deform_kernel::spring::{
    batina_stiffness, inverse_volume_factors, scale_stiffness, wall_distance_factors,
    wall_distances,
};
use deform_kernel::{graph_from_edges, graph_from_edges_len, Graph, Quat};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    coords: Vec<[i8; 2]>,
    edges: Vec<[u8; 2]>,
    wall: Vec<u8>,
    exponent: i8,
    values: Vec<i16>,
    radius: i8,
    rotations: Vec<[i8; 4]>,
    special: u8,
}

fn special(v: f64, k: u8) -> f64 {
    match k % 16 {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => -1.0,
        3 => 0.0,
        4 => 1e300,
        _ => v,
    }
}

fuzz_target!(|inp: Input| {
    let n = inp.coords.len().min(40);
    if n < 2 {
        return;
    }
    let points: Vec<[f64; 2]> = inp.coords[..n]
        .iter()
        .map(|c| [f64::from(c[0]) / 8.0, f64::from(c[1]) / 8.0])
        .collect();

    // Wall distances and factors.
    let wall: Vec<u32> = inp
        .wall
        .iter()
        .take(10)
        .map(|&w| u32::from(w) % (n as u32 + 2))
        .collect();
    let mut d = vec![7.0; n];
    match wall_distances(&points, &wall, &mut d) {
        Ok(()) => assert!(d.iter().all(|&x| x.is_finite() && x >= 0.0)),
        Err(_) => assert!(d.iter().all(|&x| x == 7.0)),
    }
    let exponent = f64::from(inp.exponent) / 16.0;
    let mut f: Vec<f64> = (0..n)
        .map(|i| {
            let v = f64::from(inp.values.get(i).copied().unwrap_or(1)) / 64.0;
            if i == 0 {
                special(v, inp.special)
            } else {
                v.abs()
            }
        })
        .collect();
    let before = f.clone();
    let r = if inp.special & 16 == 0 {
        wall_distance_factors(&mut f, exponent)
    } else {
        inverse_volume_factors(&mut f, exponent)
    };
    match r {
        Ok(()) => assert!(f.iter().all(|&x| x.is_finite() && x > 0.0)),
        Err(_) => assert_eq!(
            f.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            before.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
        ),
    }

    // A graph and Batina stiffness, scaled by the factors.
    let edges: Vec<[u32; 2]> = inp
        .edges
        .iter()
        .take(60)
        .map(|e| [u32::from(e[0]) % n as u32, u32::from(e[1]) % n as u32])
        .filter(|e| e[0] != e[1])
        .collect();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_edges_len(&edges)];
    let Ok(used) = graph_from_edges(n, &edges, &mut offsets, &mut targets) else {
        return;
    };
    let Ok(g) = Graph::new(&offsets, &targets[..used]) else {
        return;
    };
    let mut k = vec![0.0; g.edge_count()];
    if batina_stiffness(&g, &points, 1.0, &mut k).is_ok() {
        let k0 = k.clone();
        match scale_stiffness(&g, &f, &mut k) {
            Ok(()) => {
                let mut e = 0;
                for (i, _, row) in g.rows() {
                    for &j in row {
                        let back = g.neighbors(j as usize).binary_search(&(i as u32)).unwrap();
                        let eb = offsets[j as usize] as usize + back;
                        assert_eq!(k[e].to_bits(), k[eb].to_bits());
                        assert!(k[e].is_finite() && k[e] > 0.0);
                        e += 1;
                    }
                }
            }
            Err(_) => assert_eq!(k, k0),
        }
    }

    // Reach.
    let radius = special(f64::from(inp.radius) / 8.0, inp.special >> 4);
    let dist: Vec<f64> = (0..n)
        .map(|i| f64::from(inp.values.get(i).copied().unwrap_or(0)) / 256.0)
        .collect();
    let mut t: Vec<[f64; 2]> = points.clone();
    let mut q: Vec<Quat<f64>> = (0..n)
        .map(|i| {
            let r = inp.rotations.get(i).copied().unwrap_or([16, 0, 0, 0]);
            Quat::from_array(r.map(|v| f64::from(v) / 16.0))
        })
        .collect();
    let (t0, q0) = (t.clone(), q.clone());
    match limit_reach(&dist, radius, &mut t, &mut q) {
        Ok(()) => {
            for i in 0..n {
                let len = |v: [f64; 2]| v[0].hypot(v[1]);
                assert!(len(t[i]) <= len(t0[i]));
                if dist[i] >= radius {
                    assert_eq!(t[i], [0.0, 0.0]);
                    assert_eq!(q[i].to_array(), [1.0, 0.0, 0.0, 0.0]);
                }
                assert!(q[i].is_finite());
            }
        }
        Err(_) => {
            assert_eq!(t, t0);
            assert_eq!(
                q.iter()
                    .map(|x| x.to_array().map(f64::to_bits))
                    .collect::<Vec<_>>(),
                q0.iter()
                    .map(|x| x.to_array().map(f64::to_bits))
                    .collect::<Vec<_>>()
            );
        }
    }
});
