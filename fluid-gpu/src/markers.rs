//! The bodies' and the canopy's markers on the device (fluid-proc's
//! immersed.rs): their records, and the blocks they are sorted into so
//! that spreading their pushes needs no atomics (flow.wgsl's `spread`).

use crate::flow::Flow;
use crate::kernels::bind_group;
use crate::pass::{
    Kernel, Pass, Rec, FORCING_PASSES, FORCING_RECORDS, RECORD_BYTES, SPREAD_WORKGROUP, WORKGROUP,
};
use crate::spec::{FlowBox, Side};
use gpu_device::{binding_limit, buffer, check_size, non_empty, read_back, workgroups, GpuError};

/// How the air is held at a marker.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    /// A solid body's surface: the air takes the marker's velocity.
    Body,
    /// A closed sheet (a fabric): the air's normal velocity is the sheet's,
    /// and it slips along it.
    Sheet,
    /// A porous sheet: the fabric's drag Δp = a·w + b·w|w| [Pa] on the air
    /// crossing it at w relative to it.
    Porous([f64; 2]),
}

/// One marker of a body or the canopy, in the box's frame (its low corner
/// at the origin).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Marker {
    /// Position [m].
    pub x: [f64; 3],
    /// Unit normal.
    pub normal: [f64; 3],
    /// Area [m²].
    pub area: f64,
    /// The velocity it moves with [m/s].
    pub target: [f64; 3],
    pub law: Law,
}

/// Reals a marker's record holds (flow.wgsl's MARKER): x, normal, area,
/// target, the porous law (a, b), its kind, then the air at it, its push
/// and what it has given the fluid.
pub(crate) const MARKER: usize = 24;
const ACC: usize = 19;

/// Cells a block spans along each axis.
const BLOCK: i64 = 4;

/// The markers as the device holds them: sorted by block, with the
/// blocks of each colour as (first, end) marker pairs.
pub(crate) struct Sorted {
    /// order[i]: the caller's index of the i-th marker on the device.
    pub order: Vec<usize>,
    pub records: Vec<f64>,
    /// (first, end) per block, colour after colour.
    pub table: Vec<u32>,
    /// Per non-empty colour: where its pairs start in `table` and how many.
    pub colours: Vec<(usize, usize)>,
}

impl Sorted {
    pub fn of(b: &FlowBox, markers: &[Marker]) -> Sorted {
        let places: Vec<([i64; 3], usize)> = markers.iter().map(|m| place(b, m.x)).collect();
        let mut order: Vec<usize> = (0..markers.len()).collect();
        // By colour, then block, then the caller's order (a stable sort).
        order.sort_by_key(|&k| (places[k].1, places[k].0));
        let mut records = Vec::with_capacity(markers.len() * MARKER);
        for &k in &order {
            records.extend(record(&markers[k]));
        }
        let (mut table, mut colours) = (Vec::new(), Vec::new());
        let mut i = 0;
        while i < order.len() {
            let colour = places[order[i]].1;
            let start = table.len();
            while i < order.len() && places[order[i]].1 == colour {
                let block = places[order[i]].0;
                let first = i;
                while i < order.len() && places[order[i]].0 == block && places[order[i]].1 == colour
                {
                    i += 1;
                }
                table.extend([first as u32, i as u32]);
            }
            colours.push((start, (table.len() - start) / 2));
        }
        Sorted {
            order,
            records,
            table,
            colours,
        }
    }

    /// What each marker (the caller's order) has given the fluid since the
    /// records were made, from the device's `records`.
    pub fn given(&self, records: &[f64]) -> Vec<[f64; 3]> {
        let mut out = vec![[0.0; 3]; self.order.len()];
        for (i, &k) in self.order.iter().enumerate() {
            let at = i * MARKER + ACC;
            out[k] = [records[at], records[at + 1], records[at + 2]];
        }
        out
    }
}

/// A marker's block and the block's colour. Along an axis that is not
/// periodic a block is 4 cells, its colour its parity. Along a periodic
/// axis of n cells there are ⌊n/4⌋ blocks of 4 to 7 cells each, so that
/// they tile the period; where their count is odd the last one, which
/// meets block 0 across the side, takes a third colour. Blocks of one
/// colour are then a block of at least 4 cells apart along some axis.
fn place(b: &FlowBox, x: [f64; 3]) -> ([i64; 3], usize) {
    let mut block = [0i64; 3];
    let mut colour = 0;
    for d in 0..3 {
        let n = b.n[d] as i64;
        let cell = (x[d] / b.h[d]).floor() as i64;
        let c = match b.sides[d][0] == Side::Periodic {
            true => {
                let blocks = (n / BLOCK).max(1);
                block[d] = cell.rem_euclid(n) * blocks / n;
                match blocks % 2 == 1 && blocks > 1 && block[d] == blocks - 1 {
                    true => 2,
                    false => block[d] as usize % 2,
                }
            }
            false => {
                block[d] = cell.div_euclid(BLOCK);
                block[d].rem_euclid(2) as usize
            }
        };
        colour = 3 * colour + c;
    }
    (block, colour)
}

/// A marker's record (flow.wgsl's MK_ fields).
fn record(m: &Marker) -> [f64; MARKER] {
    let mut r = [0.0; MARKER];
    r[0..3].copy_from_slice(&m.x);
    r[3..6].copy_from_slice(&m.normal);
    r[6] = m.area;
    r[7..10].copy_from_slice(&m.target);
    let (law, kind) = match m.law {
        Law::Body => ([0.0; 2], 0.0),
        Law::Sheet => ([0.0; 2], 1.0),
        Law::Porous(ab) => (ab, 2.0),
    };
    r[10..12].copy_from_slice(&law);
    r[12] = kind;
    r
}

impl Flow {
    /// Puts the bodies' and the canopy's `markers` in the flow (none: the
    /// flow alone): each step from now on forces the air at them
    /// (fluid-proc's `immersed::force`), and what each gives the fluid is
    /// summed on the device until [`Flow::take_given`].
    pub fn set_markers(&mut self, markers: &[Marker]) -> Result<(), GpuError> {
        let sorted = Sorted::of(&self.spec, markers);
        let p = self.precision;
        let (record_bytes, table_bytes) = (sorted.records.len() * p.size(), sorted.table.len() * 4);
        check_size(&self.device, "the markers", record_bytes as u64)?;
        check_size(&self.device, "the markers' blocks", table_bytes as u64)?;
        let storage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        // Room for twice as many, so that a canopy that moves does not
        // grow the buffers every window, within what a binding holds.
        let limit = binding_limit(&self.device) as usize;
        // (Whole 8-byte words: a binding's size is a multiple of 4.)
        let room = |needed: usize| ((2 * needed).min(limit) & !7).max(needed);
        let mut grown = false;
        if (record_bytes as u64) > self.buffers.markers.size() {
            let reals = room(record_bytes) / p.size();
            let bytes = non_empty(p.bytes(&vec![0.0; reals]));
            self.buffers.markers = buffer(&self.device, "markers", &bytes, storage);
            grown = true;
        }
        if (table_bytes as u64) > self.buffers.blocks.size() {
            let bytes = vec![0u8; room(table_bytes)];
            self.buffers.blocks = buffer(&self.device, "blocks", &bytes, storage);
            grown = true;
        }
        if grown {
            self.bind_group = bind_group(&self.device, &self.layout, &self.buffers);
        }
        if (record_bytes as u64) > self.buffers.readback.size() {
            self.buffers.readback = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: record_bytes as u64,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
        }
        if !markers.is_empty() {
            self.queue
                .write_buffer(&self.buffers.markers, 0, &p.bytes(&sorted.records));
            self.queue
                .write_buffer(&self.buffers.blocks, 0, bytemuck::cast_slice(&sorted.table));
        }
        self.forcing = self.forcing_passes(&sorted, markers);
        self.sorted = Some(sorted);
        Ok(())
    }

    /// The forcing passes over `sorted`, their records written: the porous
    /// sheets' drag, then FORCING_PASSES − 1 passes over the others.
    fn forcing_passes(&self, sorted: &Sorted, markers: &[Marker]) -> Vec<Pass> {
        let porous = markers.iter().any(|m| matches!(m.law, Law::Porous(_)));
        let others = markers.iter().any(|m| !matches!(m.law, Law::Porous(_)));
        let count = markers.len();
        let mut list = Vec::new();
        let mut recs = Vec::new();
        for pass in 0..FORCING_PASSES {
            let aux = (pass > 0) as usize;
            if (aux == 0 && !porous) || (aux == 1 && !others) {
                continue;
            }
            let each = Rec {
                aux,
                count,
                ..Rec::default()
            };
            for kernel in [Kernel::Interpolate, Kernel::Pushes] {
                list.push((kernel, each, workgroups(count as u32, WORKGROUP)));
            }
            for &(start, blocks) in &sorted.colours {
                let rec = Rec {
                    o: [start, 0, 0, 0],
                    aux,
                    count: blocks,
                    ..Rec::default()
                };
                list.push((
                    Kernel::Spread,
                    rec,
                    workgroups(blocks as u32, SPREAD_WORKGROUP),
                ));
            }
        }
        debug_assert!(list.len() <= FORCING_RECORDS);
        let passes = list
            .into_iter()
            .enumerate()
            .map(|(i, (kernel, rec, groups))| {
                recs.push(rec.words());
                Pass {
                    kernel,
                    op: (self.plan.forcing + i) as u32,
                    groups,
                }
            })
            .collect();
        let mut bytes = vec![0u8; recs.len() * self.op_stride as usize];
        for (k, r) in recs.iter().enumerate() {
            let at = k * self.op_stride as usize;
            bytes[at..at + RECORD_BYTES].copy_from_slice(bytemuck::cast_slice(r));
        }
        if !bytes.is_empty() {
            let at = (self.plan.forcing * self.op_stride as usize) as u64;
            self.queue.write_buffer(&self.buffers.ops, at, &bytes);
        }
        passes
    }

    /// What each marker (in the order [`Flow::set_markers`] took them)
    /// has given the fluid since the markers were set or last taken: Σ
    /// F_k ΔV_k Δt, momentum per unit density [m⁴/s]; the sums start again.
    pub fn take_given(&mut self) -> Result<Vec<[f64; 3]>, GpuError> {
        let Some(sorted) = &self.sorted else {
            return Ok(Vec::new());
        };
        if sorted.order.is_empty() {
            return Ok(Vec::new());
        }
        let size = self.precision.size();
        let bytes = (sorted.records.len() * size) as u64;
        let range = [(&self.buffers.markers, 0, bytes)];
        let read = read_back(&self.device, &self.queue, &range, &self.buffers.readback)?;
        let mut records = vec![0.0; sorted.records.len()];
        self.precision.read(&read, &mut records);
        let given = sorted.given(&records);
        self.queue.write_buffer(
            &self.buffers.markers,
            0,
            &self.precision.bytes(&sorted.records),
        );
        Ok(given)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two markers of one colour in different blocks are at least 5 cells
    /// apart along some axis (periodic distance where the axis wraps), so
    /// their kernels, ±2 cells round their own, never reach one face.
    #[test]
    fn blocks_of_one_colour_never_share_a_face() {
        for (n, periodic) in [
            ([20usize, 12, 1], true),
            ([13, 9, 7], true),
            ([16, 16, 16], false),
        ] {
            let side = if periodic {
                Side::Periodic
            } else {
                Side::Outflow
            };
            let b = FlowBox {
                n,
                h: [0.1; 3],
                sides: [[side; 2], [Side::Periodic; 2], [Side::Periodic; 2]],
                nu: 1e-5,
                density: 1.2,
            };
            let mut markers = Vec::new();
            for i in 0..2000 {
                let s = i as f64 * 0.618_034;
                let x = [0, 1, 2].map(|d| (s * (d + 1) as f64).fract() * n[d] as f64 * 0.1);
                markers.push(x);
            }
            let cell = |x: [f64; 3]| [0, 1, 2].map(|d| (x[d] / 0.1).floor() as i64);
            for (i, &a) in markers.iter().enumerate() {
                for &c in &markers[..i] {
                    let (pa, pc) = (place(&b, a), place(&b, c));
                    if pa.1 != pc.1 || pa.0 == pc.0 {
                        continue;
                    }
                    let apart = (0..3).any(|d| {
                        let nd = n[d] as i64;
                        let mut gap = (cell(a)[d] - cell(c)[d]).abs();
                        if d > 0 || periodic {
                            gap = gap.min(nd - gap);
                        }
                        gap >= 5
                    });
                    assert!(apart, "{n:?}: {a:?} and {c:?} share colour {}", pa.1);
                }
            }
        }
    }
}
