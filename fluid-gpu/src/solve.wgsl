// The solves' vector operations, sums and scalar steps (flow.wgsl's
// header holds the bindings).

// ---- Vector operations and sums ------------------------------------------

// out (o0) = y (o1; none where kind has bit 1) + c·z (o2; none where kind
// has bit 2: the zero coefficient), c = s[slot],
// negated where kind has bit 0; over the op's box.
@compute @workgroup_size(256)
fn lin(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= box_size() || skipped() {
        return;
    }
    let rel = box_index(box_coords(t));
    let c = select(s[op.slot], -s[op.slot], (op.kind & 1u) == 1u);
    var v: real = 0.0;
    if (op.kind & 2u) == 0u {
        v = rd(op.o1 + rel);
    }
    // Kind 4: the zero coefficient, z not read (0·NaN would be NaN).
    if (op.kind & 4u) == 0u {
        v += c * rd(op.o2 + rel);
    }
    wr(op.o0 + rel, v);
}

// x (o0) −= s[slot] over the op's box.
@compute @workgroup_size(256)
fn shift(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= box_size() || skipped() {
        return;
    }
    let rel = box_index(box_coords(t));
    wr(op.o0 + rel, rd(op.o0 + rel) - (s[op.slot]));
}

// Whether the whole workgroup skips this pass (a uniform value, so that
// the barriers below stay in uniform control flow).
fn workgroup_skips(local: u32) -> bool {
    if local == 0u {
        shared_flag = select(0u, 1u, skipped());
    }
    return workgroupUniformLoad(&shared_flag) == 1u;
}

// The workgroup's sum (kind 0: x·y, 1: x) or largest |x| (kind 2) over the
// op's box, x at o0 and y at o1, into part[workgroup].
@compute @workgroup_size(256)
fn reduce(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) wid: vec3<u32>,
) {
    if workgroup_skips(local) {
        return;
    }
    let t = thread(gid, groups);
    var v: real = 0.0;
    if t < box_size() {
        let rel = box_index(box_coords(t));
        let x = rd(op.o0 + rel);
        if op.kind == 0u {
            v = x * rd(op.o1 + rel);
        } else if op.kind == 1u {
            v = x;
        } else {
            v = abs(x);
        }
    }
    shared_sum[local] = v;
    combine_shared(local, op.kind == 2u);
    if local == 0u {
        part[wid.x + wid.y * groups.x] = shared_sum[0];
    }
}

// shared_sum[0] ← the sum (or the largest) of shared_sum.
fn combine_shared(local: u32, largest: bool) {
    for (var half = WG / 2u; half > 0u; half /= 2u) {
        workgroupBarrier();
        if local < half {
            let a = shared_sum[local];
            let b = shared_sum[local + half];
            shared_sum[local] = select(a + b, max(a, b), largest);
        }
    }
    workgroupBarrier();
}

// s[slot] ← the sum (kind 0), the largest (1) or the mean over `aux`
// entries (2) of the op.count partial sums.
@compute @workgroup_size(256)
fn finish(@builtin(local_invocation_index) local: u32) {
    if workgroup_skips(local) {
        return;
    }
    let largest = op.kind == 1u;
    var v: real = 0.0;
    for (var i = local; i < op.count; i += WG) {
        v = select(v + part[i], max(v, part[i]), largest);
    }
    shared_sum[local] = v;
    combine_shared(local, largest);
    if local == 0u {
        var total = shared_sum[0];
        if op.kind == 2u {
            total = total / real(op.aux);
        }
        s[op.slot] = total;
    }
}

// The solves' scalar arithmetic, on one thread: op.kind names the step.
@compute @workgroup_size(1)
fn scalar() {
    if skipped() {
        return;
    }
    let b = op.solve;
    switch op.kind {
        // Viscous start: stop at once where b = 0 (δ = 0) or r is small.
        case 0u: {
            let norm_b = sqrt(s[b + BB]);
            if norm_b == 0.0 {
                s[b + DONE] = 2.0;
                return;
            }
            s[b + GOAL] = s[TOL_V] * norm_b;
            s[b + SCALE] = norm_b;
            if sqrt(s[b + RR]) <= s[b + GOAL] {
                s[b + DONE] = 1.0;
            }
        }
        // The step along p: rr/pq (viscous, kind 1) or rz/pq (pressure, 2).
        case 1u, 2u: {
            let step = select(s[b + RZ], s[b + RR], op.kind == 1u) / s[b + PQ];
            if !is_finite(step) {
                s[b + FAIL] = 1.0;
                s[b + DONE] = 1.0;
                return;
            }
            s[b + STEP] = step;
        }
        // Viscous next: stop, or β = rr_new/rr.
        case 3u: {
            s[b + ITER] += 1.0;
            if sqrt(s[b + RRN]) <= s[b + GOAL] {
                s[b + DONE] = 1.0;
                return;
            }
            s[b + BETA] = s[b + RRN] / s[b + RR];
            s[b + RR] = s[b + RRN];
        }
        // Pressure start: ‖b‖ of b's mean-free part where A is singular;
        // stop relative to the larger of it and the first residual.
        case 4u: {
            var mean: real = 0.0;
            if SINGULAR {
                mean = s[b + MEANB];
            }
            let norm_b = sqrt(max(s[b + BB] - s[CELLS] * mean * mean, 0.0));
            let res = sqrt(s[b + RR]);
            let scale = max(norm_b, res);
            s[b + SCALE] = scale;
            s[b + GOAL] = s[TOL_P] * scale;
            if res <= s[b + GOAL] || scale == 0.0 {
                s[b + DONE] = 1.0;
            }
        }
        // Pressure residual: stop once small.
        case 5u: {
            s[b + ITER] += 1.0;
            s[b + RR] = s[b + RRN];
            if sqrt(s[b + RRN]) <= s[b + GOAL] {
                s[b + DONE] = 1.0;
            }
        }
        // Pressure next: β = rz_new/rz.
        default: {
            s[b + BETA] = s[b + RZN] / s[b + RZ];
            s[b + RZ] = s[b + RZN];
        }
    }
}

