//! The `dk_exchange` callbacks of the C-ABI partitioned tests without MPI: each "process" is
//! a thread, reductions go through one slot per rank and a barrier, halos through a mailbox.
//! A rank's `max` can report a failure at a chosen call (after taking its part).
#![allow(unsafe_code)] // being called back through `extern "C"` is the point
#![allow(dead_code)] // each test file uses its own part

use std::collections::HashMap;
use std::ffi::c_void;
use std::sync::{Barrier, Mutex};

use deform_kernel_ffi::graph::dk_cells;
use deform_kernel_ffi::partition::dk_partition;
use deform_meshgen::partition::LocalView;

/// What the threads share: one slot per rank for reductions, a mailbox for halos.
pub struct Shared {
    pub barrier: Barrier,
    pub slots: Mutex<Vec<Vec<u64>>>,
    pub mail: Mutex<HashMap<(u32, u32), Vec<f64>>>,
}

/// One thread's exchange: its rank and, for the failure tests, the callback call at which it
/// reports a failure (after taking part).
pub struct Rank<'s> {
    pub rank: u32,
    pub shared: &'s Shared,
    pub fail_max_at: Option<usize>,
    pub calls: usize,
}

impl Rank<'_> {
    /// Every rank's `data` (as bits), after all have posted theirs.
    pub fn all_gather(&mut self, data: Vec<u64>) -> Vec<Vec<u64>> {
        self.shared.slots.lock().unwrap()[self.rank as usize] = data;
        self.shared.barrier.wait();
        let all = self.shared.slots.lock().unwrap().clone();
        self.shared.barrier.wait();
        all
    }
}

fn user<'a>(u: *mut c_void) -> &'a mut Rank<'a> {
    // SAFETY: every test passes a live `Rank` of its own thread as `user`.
    unsafe { &mut *(u as *mut Rank<'a>) }
}

pub unsafe extern "C" fn sum_words(u: *mut c_void, words: *mut i64, len: usize) -> i32 {
    // SAFETY: the kernel passes `len` live words.
    let w = unsafe { std::slice::from_raw_parts_mut(words, len) };
    let all = user(u).all_gather(w.iter().map(|&x| x as u64).collect());
    for (k, x) in w.iter_mut().enumerate() {
        *x = all.iter().fold(0i64, |s, r| s.wrapping_add(r[k] as i64));
    }
    0
}

pub unsafe extern "C" fn max(u: *mut c_void, values: *mut f64, len: usize) -> i32 {
    // SAFETY: the kernel passes `len` live values.
    let v = unsafe { std::slice::from_raw_parts_mut(values, len) };
    let me = user(u);
    let all = me.all_gather(v.iter().map(|x| x.to_bits()).collect());
    for (k, x) in v.iter_mut().enumerate() {
        *x = all
            .iter()
            .map(|r| f64::from_bits(r[k]))
            .fold(f64::MIN, f64::max);
    }
    me.calls += 1;
    i32::from(me.fail_max_at == Some(me.calls))
}

/// Neighbour `k`'s list of a CSR pair.
fn list<'a>(offsets: &'a [u32], items: &'a [u32], k: usize) -> &'a [u32] {
    &items[offsets[k] as usize..offsets[k + 1] as usize]
}

pub unsafe extern "C" fn halo(
    u: *mut c_void,
    p: *const dk_partition,
    field: *mut f64,
    len: usize,
    width: usize,
) -> i32 {
    // SAFETY: the kernel passes the caller's partition (arrays of its lengths) and the field.
    let (p, f) = unsafe { (&*p, std::slice::from_raw_parts_mut(field, len)) };
    // SAFETY: as above.
    let arr = |q: *const u32, n: usize| unsafe { std::slice::from_raw_parts(q, n) };
    let ranks = arr(p.neighbour_ranks, p.neighbour_ranks_len);
    let (so, s) = (
        arr(p.send_offsets, p.send_offsets_len),
        arr(p.send, p.send_len),
    );
    let (ro, r) = (
        arr(p.recv_offsets, p.recv_offsets_len),
        arr(p.recv, p.recv_len),
    );
    let me = user(u);
    for (k, &to) in ranks.iter().enumerate() {
        let packed: Vec<f64> = list(so, s, k)
            .iter()
            .flat_map(|&i| f[i as usize * width..][..width].to_vec())
            .collect();
        me.shared.mail.lock().unwrap().insert((me.rank, to), packed);
    }
    me.shared.barrier.wait();
    for (k, &from) in ranks.iter().enumerate() {
        let got = me.shared.mail.lock().unwrap()[&(from, me.rank)].clone();
        for (q, &i) in list(ro, r, k).iter().enumerate() {
            f[i as usize * width..][..width].copy_from_slice(&got[q * width..][..width]);
        }
    }
    me.shared.barrier.wait();
    0
}

/// The C view of a thread's partition (`LocalView`'s lists, borrowed).
pub fn c_partition<const D: usize>(v: &LocalView<D>) -> dk_partition {
    dk_partition {
        rank: v.rank,
        size: v.size,
        owned: v.owned,
        global_count: v.global_count,
        global_ids: v.global_ids.as_ptr(),
        global_ids_len: v.global_ids.len(),
        neighbour_ranks: v.ranks.as_ptr(),
        neighbour_ranks_len: v.ranks.len(),
        send_offsets: v.send_offsets.as_ptr(),
        send_offsets_len: v.send_offsets.len(),
        send: v.send.as_ptr(),
        send_len: v.send.len(),
        recv_offsets: v.recv_offsets.as_ptr(),
        recv_offsets_len: v.recv_offsets.len(),
        recv: v.recv.as_ptr(),
        recv_len: v.recv.len(),
    }
}

/// The C view of a thread's local cells (borrowed).
pub fn c_cells<const D: usize>(v: &LocalView<D>) -> dk_cells {
    dk_cells {
        offsets: v.cell_offsets.as_ptr(),
        offsets_len: v.cell_offsets.len(),
        nodes: v.cell_nodes.as_ptr(),
        nodes_len: v.cell_nodes.len(),
        kinds: v.cell_kinds.as_ptr(),
        kinds_len: v.cell_kinds.len(),
    }
}
