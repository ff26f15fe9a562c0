//! Reverse Cuthill–McKee (`kernel/src/order/rcm.rs`): on generated meshes numbered at random
//! and on the public SU2 meshes under cli/tests/data, the band shrinks to about what
//! scipy.sparse.csgraph.reverse_cuthill_mckee reaches on the same graph (measured by the
//! Python reference `ref_rcm.py`, which also re-measures the kernel's order independently);
//! components come out contiguous; the order is deterministic.

#[path = "../support/mod.rs"]
mod support;

use std::path::{Path, PathBuf};

use deform_kernel::order::{index_distance, rcm_order, Permutation};
use deform_kernel::Cells;
use deform_meshgen::{box_with_inner_box3, naca_triangulated, AirfoilGrid};
use support::order::{bandwidth, edges_of, renumbered, OwnedGraph, OwnedPerm};
use support::python::run_script;

fn here() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("order")
}

fn rcm(g: &deform_kernel::Graph<'_>) -> OwnedPerm {
    let n = g.node_count();
    let (mut order, mut inverse) = (vec![0; n], vec![0; n]);
    rcm_order(g, &mut order, &mut inverse).unwrap();
    Permutation::new(&order, &inverse).expect("rcm returns a permutation");
    OwnedPerm { order, inverse }
}

/// (bandwidth, profile) of the original numbering, of `ours` and of scipy's RCM, as the
/// Python reference measures them on `edges`.
fn reference(name: &str, n: usize, edges: &[[u32; 2]], ours: &OwnedPerm) -> [[u64; 2]; 3] {
    let dir = std::env::temp_dir().join(format!("deform-order-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let graph = dir.join("graph.txt");
    let order = dir.join("order.txt");
    let mut g = format!("{n}\n");
    for [a, b] in edges {
        g.push_str(&format!("{a} {b}\n"));
    }
    std::fs::write(&graph, g).unwrap();
    let o: String = ours.order.iter().map(|v| format!("{v}\n")).collect();
    std::fs::write(&order, o).unwrap();
    let out = run_script(
        &here().join("ref_rcm.py"),
        &["measure", graph.to_str().unwrap(), order.to_str().unwrap()],
    );
    std::fs::remove_dir_all(&dir).ok();
    let rows: Vec<[u64; 2]> = out
        .lines()
        .map(|l| {
            let v: Vec<u64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            [v[0], v[1]]
        })
        .collect();
    [rows[0], rows[1], rows[2]]
}

/// Runs RCM on the graph of `edges` and checks it against scipy's; returns the three rows.
fn compare_with_scipy(name: &str, n: usize, edges: &[[u32; 2]]) -> [[u64; 2]; 3] {
    let og = OwnedGraph::from_edges(n, edges);
    let g = og.graph();
    let ours = rcm(&g);
    let [orig, mine, scipy] = reference(name, n, edges, &ours);
    let d = index_distance(&g, Some(ours.view())).unwrap();
    assert_eq!(
        u64::from(d.max),
        mine[0],
        "{name}: the kernel's bandwidth = the reference's"
    );
    assert_eq!(d.max, bandwidth(edges, &ours.inverse));
    // A mesh numbered without regard to locality (band above a quarter of the nodes) gets a
    // narrower band; one numbered along its grid lines may keep a narrower band than RCM's.
    if orig[0] > n as u64 / 4 {
        assert!(
            mine[0] < orig[0],
            "{name}: band {} not below {}",
            mine[0],
            orig[0]
        );
    }
    // A pseudo-peripheral start is at least as good as scipy's minimum-degree start up to a
    // little: within 10% of its bandwidth and profile.
    assert!(
        mine[0] * 10 <= scipy[0] * 11,
        "{name}: band {mine:?} vs scipy {scipy:?}"
    );
    assert!(
        mine[1] * 10 <= scipy[1] * 11,
        "{name}: profile {mine:?} vs scipy {scipy:?}"
    );
    eprintln!("{name}: n {n}, original {orig:?}, kernel {mine:?}, scipy {scipy:?}");
    [orig, mine, scipy]
}

#[test]
fn public_su2_meshes_get_scipys_band() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cli/tests/data");
    for file in [
        "cylinder_half_unmarked_wall.su2",
        "naca64a010_hybrid_clockwise.su2",
        "mixed_elements_knowles.su2",
        "sphere_slice_2syms.su2",
        "brick_hex_periodic_ffd.su2",
    ] {
        let path = data.join(file);
        let out = run_script(
            &here().join("ref_rcm.py"),
            &["edges", path.to_str().unwrap()],
        );
        let mut lines = out.lines();
        let n: usize = lines.next().unwrap().parse().unwrap();
        let edges: Vec<[u32; 2]> = lines
            .map(|l| {
                let mut it = l.split_whitespace().map(|x| x.parse::<u32>().unwrap());
                [it.next().unwrap(), it.next().unwrap()]
            })
            .collect();
        compare_with_scipy(file, n, &edges);
    }
}

/// A mesh's cell offsets, nodes and kinds.
type MeshArrays<'a> = (&'a [u32], &'a [u32], &'a [u8]);

#[test]
fn generated_meshes_numbered_at_random_get_a_narrow_band() {
    let naca = naca_triangulated(&AirfoilGrid::default()).unwrap();
    let boxed = box_with_inner_box3(14, 4).unwrap();
    let cases: [(&str, usize, MeshArrays<'_>); 2] = [
        (
            "naca",
            naca.node_count(),
            (&naca.offsets, &naca.nodes, &naca.kinds),
        ),
        (
            "box",
            boxed.node_count(),
            (&boxed.offsets, &boxed.nodes, &boxed.kinds),
        ),
    ];
    for (name, n, (offsets, nodes, kinds)) in cases {
        let ordered = Cells::new(n, offsets, nodes, kinds).unwrap();
        let g0 = OwnedGraph::from_cells(&ordered);
        let generator_band = index_distance(&g0.graph(), None).unwrap().max;
        let shuffle = OwnedPerm::random(n, 3);
        let shuffled: Vec<u32> = nodes.iter().map(|&v| shuffle.inverse[v as usize]).collect();
        let og = OwnedGraph::from_cells(&Cells::new(n, offsets, &shuffled, kinds).unwrap());
        let edges = edges_of(&og.graph());
        let [orig, mine, _] = compare_with_scipy(name, n, &edges);
        // Random numbering spreads edges over the whole index range; RCM brings the band
        // back to within twice the generator's line-by-line numbering.
        assert!(orig[0] > n as u64 / 2, "{name}: {orig:?}");
        assert!(
            mine[0] <= 2 * u64::from(generator_band),
            "{name}: {mine:?} vs {generator_band}"
        );
    }
}

#[test]
fn components_are_contiguous_and_the_order_is_deterministic() {
    // Three paths (numbered interleaved) and two isolated nodes.
    let n = 17;
    let mut edges = Vec::new();
    for c in 0..3u32 {
        let nodes: Vec<u32> = (0..5).map(|k| c + 3 * k).collect();
        for w in nodes.windows(2) {
            edges.push([w[0], w[1]]);
        }
    }
    let og = OwnedGraph::from_edges(n, &edges);
    let g = og.graph();
    let p = rcm(&g);
    assert_eq!(p, rcm(&g));
    assert_eq!(index_distance(&g, Some(p.view())).unwrap().max, 1);
    for c in 0..3u32 {
        let mut pos: Vec<u32> = (0..5).map(|k| p.inverse[(c + 3 * k) as usize]).collect();
        pos.sort_unstable();
        assert_eq!(pos[4] - pos[0], 4, "component {c} contiguous: {pos:?}");
    }
    // A permuted copy of the same graph gets a band as narrow.
    let shuffle = OwnedPerm::random(n, 9);
    let (_, nodes) = renumbered::<1>(&vec![[0.0]; n], &edges.concat(), &shuffle);
    let e2: Vec<[u32; 2]> = nodes.chunks(2).map(|c| [c[0], c[1]]).collect();
    let og2 = OwnedGraph::from_edges(n, &e2);
    let p2 = rcm(&og2.graph());
    assert_eq!(
        index_distance(&og2.graph(), Some(p2.view())).unwrap().max,
        1
    );
}
