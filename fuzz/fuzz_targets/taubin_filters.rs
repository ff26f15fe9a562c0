//! Target 6: Taubin λ|μ filters, structured and on graphs, on arbitrary small fields: bitwise
//! equal to the naive host reference, finite, and within the provable one-step growth bound
//! (‖F‖∞ grows by at most 1.2204 per λ|μ iteration with the paper's 0.330 / −0.334).
#![no_main]

use arbitrary::Arbitrary;
use deform_host_tests::taubin_ref::{graph_filter, structured_filter};
use deform_kernel::taubin::{
    graph_scratch_len, smooth_graph, smooth_structured, structured_scratch_len, GraphOptions,
    StructuredOptions, TaubinParams,
};
use deform_kernel::Directions;
use deform_kernel::{graph_from_edges, graph_from_edges_len, Block, Graph};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    dims: [u8; 3],
    values: Vec<i16>,
    mirror: [bool; 3],
    pins: Vec<bool>,
    iterations: u8,
    edges: Vec<[u8; 2]>,
}

fuzz_target!(|inp: Input| {
    let dims = [
        (inp.dims[0] % 7) as usize + 1,
        (inp.dims[1] % 5) as usize + 1,
        (inp.dims[2] % 4) as usize + 1,
    ];
    let n = dims[0] * dims[1] * dims[2];
    let field: Vec<f64> = (0..n)
        .map(|i| f64::from(inp.values.get(i).copied().unwrap_or(0)) / 256.0)
        .collect();
    let pinned: Vec<u8> = (0..n)
        .map(|i| u8::from(inp.pins.get(i).copied().unwrap_or(false)))
        .collect();
    let iterations = (inp.iterations % 6) as usize;
    let p = TaubinParams::paper();
    let block = Block::new(dims).unwrap();
    let opts = StructuredOptions {
        fixed: Some(&pinned),
        mirror: Directions::from_flags(inp.mirror),
    };
    let mut got = field.clone();
    let mut scratch = vec![0.0; structured_scratch_len(&block)];
    smooth_structured(&block, &mut got, p, iterations, &opts, &mut scratch).unwrap();
    let want = structured_filter(
        dims,
        &field,
        p.lambda,
        p.mu,
        iterations,
        inp.mirror,
        Some(&pinned),
    );
    let sup0 = field.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let bound = sup0 * 1.2204f64.powi(iterations as i32) * (1.0 + 1e-12);
    for (g, w) in got.iter().zip(&want) {
        assert_eq!(g.to_bits(), w.to_bits());
        assert!(g.is_finite() && g.abs() <= bound, "{g} exceeds {bound}");
    }

    // The same filter on a graph over the first few nodes.
    let m = n.min(16);
    let edges: Vec<[u32; 2]> = inp
        .edges
        .iter()
        .map(|e| [(e[0] as usize % m) as u32, (e[1] as usize % m) as u32])
        .filter(|e| e[0] != e[1])
        .collect();
    let mut offsets = vec![0u32; m + 1];
    let mut targets = vec![0u32; graph_from_edges_len(&edges)];
    let Ok(used) = graph_from_edges(m, &edges, &mut offsets, &mut targets) else {
        return;
    };
    targets.truncate(used);
    let g = Graph::new(&offsets, &targets).unwrap();
    let values: Vec<[f64; 2]> = field.iter().take(m).map(|&x| [x, 0.5 * x]).collect();
    let fixed = &pinned[..m];
    let mut gv = values.clone();
    let mut gs = vec![[0.0f64; 2]; graph_scratch_len(&g)];
    let gopts = GraphOptions {
        weights: None,
        fixed: Some(fixed),
    };
    smooth_graph(&g, &mut gv, p, iterations, &gopts, &mut gs).unwrap();
    let gw = graph_filter(
        &offsets,
        &targets,
        None,
        Some(fixed),
        &values,
        p.lambda,
        p.mu,
        iterations,
    );
    for (a, b) in gv.iter().zip(&gw) {
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
    }
});
