//! The flow step's loops over a box of faces or cells, on every thread of
//! the pool, with the same result to the bit on any number of threads.
//!
//! A padded array (`padded.rs`) is rows along x, one after the other: a
//! box's rows are disjoint slices of it, so each thread writes its rows
//! of the outputs and reads whatever it likes of the inputs. Sums (the
//! conjugate gradients' dot products, a mean) are not taken here: their
//! callers take them on one thread, entry after entry in the grid's order,
//! as before the loops ran on threads. A sum split among threads would be
//! the same on any number of them if its parts were fixed, but not the
//! same bits as the one-thread sum, and the C-9's inflation is chaotic
//! enough that round-off moves its steady descent by percents (issue 43,
//! item 5: its spread went from 1.8 % to 5.1 % with sums taken row by
//! row). So the results are those of the serial step, bit for bit. What
//! keeps the second thread busy while one sums is other work that does not
//! need the sum: the three velocity components' predictions run side by
//! side (`component.rs`, `by_component`), and the pressure solve sums
//! its residual beside φ's update (`poisson.rs`).

use crate::layout::Layout;
use rayon::prelude::*;

/// Entries per task below which rows are not split among threads.
const ENTRIES_PER_TASK: usize = 8192;

/// Whether a loop over `entries` entries is split among threads.
pub fn worth_threads(entries: usize) -> bool {
    entries > ENTRIES_PER_TASK
}

/// One row of the box: the face (or cell) it starts at and that face's
/// index in the padded array.
#[derive(Debug, Clone, Copy)]
pub struct Row {
    pub first: [isize; 3],
    pub at: usize,
    /// Entries along x.
    pub len: usize,
    /// Where the row starts in each output's row slice.
    pub offset: usize,
}

/// Calls `f(row, outs)` for every row along x of the box `range` of
/// `lay`, with each output's slice for that row (`outs[n][row.offset + i]`
/// is entry `row.at + i`), on the pool's threads.
pub fn each<const N: usize>(
    lay: &Layout,
    range: [[isize; 2]; 3],
    outs: [&mut [f64]; N],
    f: impl Fn(Row, &mut [&mut [f64]; N]) + Sync,
) {
    let dims = lay.dims();
    let row_len = dims[0];
    let len = (range[0][1] - range[0][0]).max(0) as usize;
    if len == 0 || range[1][1] <= range[1][0] || range[2][1] <= range[2][0] {
        return;
    }
    let offset = (range[0][0] + lay.g[0] as isize) as usize;
    let inside = |j: isize, k: isize| {
        (range[1][0]..range[1][1]).contains(&j) && (range[2][0]..range[2][1]).contains(&k)
    };
    let mut chunks = outs.map(|o| o.chunks_mut(row_len));
    let rows: Vec<(Row, [&mut [f64]; N])> = (0..dims[1] * dims[2])
        .filter_map(|r| {
            let slices = chunks
                .each_mut()
                .map(|c| c.next().expect("a row of each output"));
            let j = (r % dims[1]) as isize - lay.g[1] as isize;
            let k = (r / dims[1]) as isize - lay.g[2] as isize;
            inside(j, k).then(|| {
                let first = [range[0][0], j, k];
                let row = Row {
                    first,
                    at: lay.at(first),
                    len,
                    offset,
                };
                (row, slices)
            })
        })
        .collect();
    let per_task = (ENTRIES_PER_TASK / len).max(1);
    match rows.len() > per_task {
        true => rows
            .into_par_iter()
            .with_min_len(per_task)
            .for_each(|(row, mut slices)| f(row, &mut slices)),
        // One task's worth: not worth waking another thread.
        false => rows
            .into_iter()
            .for_each(|(row, mut slices)| f(row, &mut slices)),
    }
}

/// `f(j, k, row)` for every row along x of a plain array of `n` entries
/// per axis (cells, or one component's faces, without ghosts), on the
/// pool's threads.
pub fn each_plain(out: &mut [f64], n: [usize; 3], f: impl Fn(usize, usize, &mut [f64]) + Sync) {
    out[..n.iter().product()]
        .par_chunks_mut(n[0])
        .enumerate()
        .with_min_len((ENTRIES_PER_TASK / n[0]).max(1))
        .for_each(|(r, row)| f(r % n[1], r / n[1], row));
}

/// Entries per task of [`for_each`].
const CHUNK: usize = 4096;

/// `f(&mut a[i], i)` for every entry of a plain array, on the pool's threads.
pub fn for_each(a: &mut [f64], f: impl Fn(&mut f64, usize) + Sync) {
    if a.len() <= CHUNK {
        return a.iter_mut().enumerate().for_each(|(i, x)| f(x, i));
    }
    a.par_chunks_mut(CHUNK).enumerate().for_each(|(c, chunk)| {
        for (i, x) in chunk.iter_mut().enumerate() {
            f(x, c * CHUNK + i);
        }
    });
}

/// `dst = src`, on the pool's threads.
pub fn copy(dst: &mut [f64], src: &[f64]) {
    assert_eq!(dst.len(), src.len(), "copy between arrays of one length");
    for_each(dst, |d, i| *d = src[i]);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every entry of the box, and none outside it, is written, the same
    /// on one thread and on several.
    #[test]
    fn every_entry_of_the_box_is_written_once_on_any_thread_count() {
        let lay = Layout::cells([37, 23, 11]);
        let n = lay.dims().iter().product();
        let x: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let range = lay.unknown_box();
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut out = vec![0.0; n];
            pool.install(|| {
                each(&lay, range, [&mut out], |row, [o]| {
                    for i in 0..row.len {
                        o[row.offset + i] += 2.0 * x[row.at + i];
                    }
                })
            });
            out
        };
        let one = run(1);
        for threads in [2, 3, 7] {
            assert_eq!(run(threads), one, "{threads} threads");
        }
        let mut written = 0;
        lay.for_box(range, |_, p| {
            assert_eq!(one[p], 2.0 * x[p]);
            written += 1;
        });
        assert_eq!(written, 37 * 23 * 11);
        assert_eq!(one.iter().filter(|&&v| v != 0.0).count(), written);
    }
}
