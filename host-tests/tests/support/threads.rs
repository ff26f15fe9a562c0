//! Processes as threads for the partitioned tests: each thread gets an [`Exchange`] over
//! shared memory behind barriers (sums, maxima, and the halo exchange through mailboxes), so
//! a partitioned run is checked in one process without MPI.

use std::collections::HashMap;
use std::sync::{Barrier, Mutex};

use deform_kernel::partition::{Exchange, Halo};

/// What the threads share: a barrier, one slot per thread, and mailboxes.
#[derive(Debug)]
pub struct Board {
    barrier: Barrier,
    words: Mutex<Vec<Vec<i64>>>,
    reals: Mutex<Vec<Vec<f64>>>,
    mail: Mutex<HashMap<(u32, u32), Vec<f64>>>,
}

/// One thread's [`Exchange`] over the board.
#[derive(Debug)]
pub struct Threads<'b> {
    rank: u32,
    board: &'b Board,
}

impl Threads<'_> {
    /// Puts `mine` in this thread's slot, waits for all, folds every slot into `out`.
    fn all_reduce<X: Copy>(
        &self,
        slots: &Mutex<Vec<Vec<X>>>,
        out: &mut [X],
        f: impl Fn(X, X) -> X,
    ) {
        slots.lock().unwrap()[self.rank as usize] = out.to_vec();
        self.board.barrier.wait();
        {
            let all = slots.lock().unwrap();
            let first = all[0].clone();
            for (k, o) in out.iter_mut().enumerate() {
                *o = all.iter().skip(1).fold(first[k], |a, s| f(a, s[k]));
            }
        }
        self.board.barrier.wait();
    }
}

impl Exchange<f64> for Threads<'_> {
    fn sum_words(&self, words: &mut [i64]) {
        self.all_reduce(&self.board.words, words, i64::wrapping_add);
    }
    fn max(&self, values: &mut [f64]) {
        self.all_reduce(&self.board.reals, values, f64::max);
    }
    fn exchange(&self, halo: &Halo<'_>, field: &mut [f64], width: usize) {
        for (r, send, _) in halo.neighbours() {
            let packed = send
                .iter()
                .flat_map(|&i| field[i as usize * width..][..width].to_vec())
                .collect();
            self.board
                .mail
                .lock()
                .unwrap()
                .insert((self.rank, r), packed);
        }
        self.board.barrier.wait();
        for (r, _, recv) in halo.neighbours() {
            let got = self.board.mail.lock().unwrap().remove(&(r, self.rank));
            let got = got.expect("a neighbour sent nothing");
            for (&i, v) in recv.iter().zip(got.chunks_exact(width)) {
                field[i as usize * width..][..width].copy_from_slice(v);
            }
        }
        self.board.barrier.wait();
    }
}

/// Runs `f(rank, exchange)` on `size` threads and returns their results in rank order.
pub fn on_threads<R: Send>(size: usize, f: impl Fn(u32, &Threads<'_>) -> R + Sync) -> Vec<R> {
    let board = Board {
        barrier: Barrier::new(size),
        words: Mutex::new(vec![Vec::new(); size]),
        reals: Mutex::new(vec![Vec::new(); size]),
        mail: Mutex::new(HashMap::new()),
    };
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..size as u32)
            .map(|rank| {
                let (board, f) = (&board, &f);
                s.spawn(move || f(rank, &Threads { rank, board }))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    })
}
