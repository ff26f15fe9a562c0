//! Target 15: linear elasticity on arbitrary small 2D meshes of triangles and quads (any node
//! indices, degenerate and inverted cells, duplicate points), moduli choices, Poisson ratios
//! (in and out of range, NaN), increments, fixed masks and displacements: never panics; an
//! error leaves the points bit-identical; on success every point is finite and the fixed
//! nodes end exactly at `points + displacement`. Before the increments, `rigid_layer` with
//! arbitrary wall indices (in and out of range), rotations (zero among them) and thicknesses
//! (negative, NaN): an error leaves the mask and the displacement bit-identical; on success the
//! nodes it reports are newly fixed, every node fixed before keeps its displacement, every
//! value is finite, and the increments then run on the layered mask.
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::elasticity::{
    deform_incremental, elasticity_graph, elasticity_graph_len, rigid_layer, IncrementBuffers,
    Increments, Modulus,
};
use deform_kernel::spring::SolveOptions;
use deform_kernel::{Cells, Graph, Quat};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    coords: Vec<[i8; 2]>,
    cells: Vec<[u8; 4]>,
    quads: u16,
    fixed: u32,
    moves: Vec<[i8; 2]>,
    modulus: u8,
    poisson: i8,
    steps: u8,
    wall: Vec<u8>,
    layer_wall: Vec<u8>,
    layer_turn: [i8; 4],
    layer_thickness: i8,
}

/// `rigid_layer` on copies of `fixed` and `disp`, checked; the layered pair on success.
fn layered(
    inp: &Input,
    points: &[[f64; 2]],
    fixed: &[u8],
    disp: &[[f64; 2]],
) -> Option<(Vec<u8>, Vec<[f64; 2]>)> {
    let n = points.len() as u32;
    let wall: Vec<u32> = inp
        .layer_wall
        .iter()
        .take(6)
        .map(|&w| u32::from(w) % (n + 2))
        .collect();
    let q = Quat::from_array(inp.layer_turn.map(|c| f64::from(c) / 64.0));
    let rotations = vec![q; wall.len()];
    let thickness = match inp.layer_thickness {
        i8::MIN => f64::NAN,
        t => f64::from(t) / 32.0,
    };
    let (mut f, mut d) = (fixed.to_vec(), disp.to_vec());
    match rigid_layer(points, &wall, &rotations, thickness, &mut f, &mut d) {
        Ok(added) => {
            let new = (0..points.len())
                .filter(|&i| fixed[i] == 0 && f[i] != 0)
                .count();
            assert_eq!(added, new);
            for i in 0..points.len() {
                assert!(f[i] != 0 || fixed[i] == 0, "a fixed node was freed");
                if fixed[i] != 0 {
                    assert_eq!(d[i].map(f64::to_bits), disp[i].map(f64::to_bits));
                }
            }
            assert!(d.iter().flatten().all(|x| x.is_finite()));
            Some((f, d))
        }
        Err(_) => {
            assert_eq!(f, fixed);
            let bits = |v: &[[f64; 2]]| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&d), bits(disp));
            None
        }
    }
}

fuzz_target!(|inp: Input| {
    let n = inp.coords.len().min(24);
    if n < 3 {
        return;
    }
    let points: Vec<[f64; 2]> = inp.coords[..n]
        .iter()
        .map(|c| [f64::from(c[0]) / 8.0, f64::from(c[1]) / 8.0])
        .collect();
    let (mut offsets, mut nodes, mut kinds) = (vec![0u32], vec![], vec![]);
    for (k, c) in inp.cells.iter().take(16).enumerate() {
        let quad = inp.quads >> (k % 16) & 1 == 1;
        let count = if quad { 4 } else { 3 };
        nodes.extend(c[..count].iter().map(|&v| u32::from(v) % n as u32));
        kinds.push(if quad { 9 } else { 5 });
        offsets.push(nodes.len() as u32);
    }
    let Ok(cells) = Cells::new(n, &offsets, &nodes, &kinds) else {
        return;
    };
    let mut go = vec![0u32; n + 1];
    let mut gt = vec![0u32; elasticity_graph_len(&cells)];
    let Ok(used) = elasticity_graph(&cells, &mut go, &mut gt) else {
        return;
    };
    let Ok(graph) = Graph::new(&go, &gt[..used]) else {
        return;
    };
    let fixed: Vec<u8> = (0..n).map(|i| (inp.fixed >> (i % 32) & 1) as u8).collect();
    let disp: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let m = inp.moves.get(i).copied().unwrap_or([0, 0]);
            [f64::from(m[0]) / 64.0, f64::from(m[1]) / 64.0]
        })
        .collect();
    let (fixed, disp) = layered(&inp, &points, &fixed, &disp).unwrap_or((fixed, disp));
    let wall: Vec<f64> = (0..n)
        .map(|i| f64::from(inp.wall.get(i).copied().unwrap_or(1)) / 16.0)
        .collect();
    let modulus = [
        Modulus::Constant,
        Modulus::InverseVolume,
        Modulus::WallDistance,
    ][usize::from(inp.modulus % 3)];
    let poisson = if inp.poisson == i8::MIN {
        f64::NAN
    } else {
        f64::from(inp.poisson) / 200.0
    };
    let params = Increments {
        modulus,
        wall_distance: (inp.modulus & 4 == 0).then_some(&wall[..]),
        poisson,
        steps: usize::from(inp.steps % 4),
    };
    let mut moduli = vec![0.0; cells.len()];
    let (mut diag, mut off) = (vec![[[0.0; 2]; 2]; n], vec![[[0.0; 2]; 2]; used]);
    let (mut cur, mut step) = (vec![[0.0; 2]; n], vec![[0.0; 2]; n]);
    let mut cg = vec![[0.0; 2]; 4 * n];
    let buffers = IncrementBuffers {
        moduli: &mut moduli,
        diag: &mut diag,
        off: &mut off,
        current: &mut cur,
        step: &mut step,
    };
    let options = SolveOptions {
        max_iterations: 200,
        ..SolveOptions::default()
    };
    let mut moved = points.clone();
    let r = deform_incremental(
        &cells,
        &graph,
        &fixed,
        &params,
        &mut moved,
        &disp,
        buffers,
        |s, u| s.solve(u, &options, &mut cg),
    );
    match r {
        Ok(_) => {
            assert!(moved.iter().flatten().all(|x| x.is_finite()));
            for i in 0..n {
                if fixed[i] != 0 {
                    let want = [points[i][0] + disp[i][0], points[i][1] + disp[i][1]];
                    assert_eq!(moved[i].map(f64::to_bits), want.map(f64::to_bits));
                }
            }
        }
        Err(_) => assert_eq!(
            moved
                .iter()
                .flatten()
                .map(|x| x.to_bits())
                .collect::<Vec<_>>(),
            points
                .iter()
                .flatten()
                .map(|x| x.to_bits())
                .collect::<Vec<_>>()
        ),
    }
});
