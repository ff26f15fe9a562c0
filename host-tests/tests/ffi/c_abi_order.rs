//! Node orders through the C ABI: builds `libdeform_kernel` (static and shared), compiles
//! `ffi/tests/order.c` (RCM and Hilbert orders of a randomly numbered grid, index distances,
//! points, cell lists and a graph with per-edge data permuted and put back, bad input that
//! must return its status and write nothing), runs it, and compares every printed order, key,
//! distance and permuted array with the kernel (`deform_kernel::order`) on the same inputs,
//! bit for bit. Needs `gcc` on PATH.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;

use deform_kernel::order::{
    gather, hilbert_order, index_distance, permute, permute_graph, rcm_order, Permutation,
};
use deform_kernel::{graph_from_edges, Graph};

fn ints(name: &str, v: &[u32]) -> String {
    let mut s = name.to_string();
    for x in v {
        s += &format!(" {x}");
    }
    s + "\n"
}

fn keys(name: &str, v: &[u64]) -> String {
    let mut s = name.to_string();
    for x in v {
        s += &format!(" {x:016X}");
    }
    s + "\n"
}

fn field<'a>(lines: &[&'a str], name: &str) -> Vec<&'a str> {
    let l = lines
        .iter()
        .find(|l| l.starts_with(&format!("{name} ")))
        .unwrap_or_else(|| panic!("no {name} line"));
    l.split_whitespace().skip(1).collect()
}

/// What order.c must print after its edges and points, computed with the kernel.
fn expected(edges: &[u32], points: &[f64]) -> String {
    let n = points.len() / 2;
    let pairs: Vec<[u32; 2]> = edges.chunks(2).map(|c| [c[0], c[1]]).collect();
    let mut offsets = vec![0; n + 1];
    let mut targets = vec![0; edges.len()];
    let used = graph_from_edges(n, &pairs, &mut offsets, &mut targets).unwrap();
    let g = Graph::new(&offsets, &targets[..used]).unwrap();
    let (mut order, mut inverse) = (vec![0; n], vec![0; n]);
    rcm_order(&g, &mut order, &mut inverse).unwrap();
    let mut out = ints("rcm", &order);
    let pts: Vec<[f64; 2]> = points.chunks(2).map(|c| [c[0], c[1]]).collect();
    let (mut ho, mut hi, mut hk) = (vec![0; n], vec![0; n], vec![0; n]);
    hilbert_order(&pts, &mut ho, &mut hi, &mut hk).unwrap();
    out += &ints("hilbert_f64", &ho);
    out += &keys("keys_f64", &hk);
    let p32: Vec<[f32; 2]> = pts.iter().map(|p| p.map(|x| x as f32)).collect();
    hilbert_order(&p32, &mut ho, &mut hi, &mut hk).unwrap();
    out += &ints("hilbert_f32", &ho);
    out += &keys("keys_f32", &hk);
    let p = Permutation::new(&order, &inverse).unwrap();
    let d0 = index_distance(&g, None).unwrap();
    let d1 = index_distance(&g, Some(p)).unwrap();
    out += &format!(
        "distance {} {}\ndistance_rcm {} {}\n",
        d0.max, d0.sum, d1.max, d1.sum
    );
    let mut moved = vec![[0.0; 2]; n];
    permute(p, &pts, &mut moved).unwrap();
    out += &hex64("moved", moved.as_flattened());
    let mut moved32 = vec![[0.0f32; 2]; n];
    permute(p, &p32, &mut moved32).unwrap();
    out += &hex32("moved_f32", moved32.as_flattened());
    let (mut po, mut pt, mut map) = (vec![0; n + 1], vec![0; used], vec![0; used]);
    permute_graph(p, &g, &mut po, &mut pt, Some(&mut map)).unwrap();
    out += &ints("graph_offsets", &po);
    out += &ints("graph_targets", &pt);
    out += &ints("edge_map", &map);
    let stiff: Vec<f64> = (0..used).map(|i| 1.0 / (i as f64 + 3.0)).collect();
    let mut ps = vec![0.0; used];
    gather(&map, &stiff, &mut ps).unwrap();
    out += &hex64("stiffness", &ps);
    let s32: Vec<f32> = stiff.iter().map(|&x| x as f32).collect();
    let mut ps32 = vec![0.0f32; used];
    gather(&map, &s32, &mut ps32).unwrap();
    out += &hex32("stiffness_f32", &ps32);
    out
}

#[test]
fn orders_from_c_equal_the_kernel_bit_for_bit() {
    let src = workspace().join("ffi/tests/order.c");
    let mut flags = c_flags();
    flags.push("-Wl,--disable-new-dtags".to_string());
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    for (link, name) in [
        (Link::Static, "order_static"),
        (Link::Shared, "order_shared"),
    ] {
        let exe = tmp(name);
        compile("gcc", std::slice::from_ref(&src), &flags, link, &exe);
        let printed = run(&exe);
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(
            lines.last(),
            Some(&"order: every check held"),
            "{name}: {printed}"
        );
        let edges: Vec<u32> = field(&lines, "edges")
            .iter()
            .map(|x| x.parse().unwrap())
            .collect();
        let points: Vec<f64> = field(&lines, "points")
            .iter()
            .map(|h| f64::from_bits(u64::from_str_radix(h, 16).unwrap()))
            .collect();
        let want = expected(&edges, &points);
        let got: String = lines[2..lines.len() - 1]
            .iter()
            .map(|l| format!("{l}\n"))
            .collect();
        for (g, e) in got.lines().zip(want.lines()) {
            let head = |s: &str| s.split(' ').next().unwrap_or("").to_string();
            assert!(
                g == e,
                "{name}: {} differs from the kernel's {}",
                head(g),
                head(e)
            );
        }
        assert_eq!(got.lines().count(), want.lines().count(), "{name}: lines");
        // The grid was numbered at random; RCM's band is about a grid row.
        let rcm_max: u32 = field(&lines, "distance_rcm")[0].parse().unwrap();
        let max: u32 = field(&lines, "distance")[0].parse().unwrap();
        assert!(rcm_max <= 2 * 13 && max > 60, "{rcm_max} {max}");
    }
}
