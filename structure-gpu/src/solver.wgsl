// The structure's explicit step on the device (dissertation chapter 5): the
// same three passes as the CPU path (structure-proc's forces/assembly.rs),
// so that one network gives the same numbers on both to round-off:
//
// - `element_slots`: every spring and damper writes its force on its first
//   node into a slot of its own (its second node gets the opposite);
// - `gather`: every node sums m·g and its slots, in the CPU's order;
// - `combine`: out ← a + c·b, or a + c·b/m where `scaled`: the kicks and
//   drifts every scheme is made of (structure-proc's integrators/mod.rs).
//
// The host prepends `alias real = f64;` (or f32 where the adapter lacks
// f64) and the constants NODES, SPRINGS, DAMPERS and DAMPING_LAW. Every
// vector (positions, velocities, forces, stage values) lives in `vecs`, 3
// reals a node, vector k at offset 3·NODES·k; each dispatch names its
// vectors in `op` (a dynamic offset into one uniform buffer per step).

struct Op {
    out: u32,
    a: u32,
    b: u32,
    // coefficient index << 1 | scaled by 1/m
    coef: u32,
}

@group(0) @binding(0) var<storage, read_write> vecs: array<real>;
@group(0) @binding(1) var<storage, read_write> slots: array<real>;
// Springs' then dampers' end nodes, 2 each.
@group(0) @binding(2) var<storage, read> ends: array<u32>;
// Springs: k, rest length, compressive tolerance, 1 for a string;
// dampers: c, slack length, 0, 0.
@group(0) @binding(3) var<storage, read> elements: array<real>;
// Mass then 1/m per node.
@group(0) @binding(4) var<storage, read> nodes: array<real>;
// start[0..=NODES], then slot << 1 | subtracted.
@group(0) @binding(5) var<storage, read> assembly: array<u32>;
// Gravity (3), then the step's coefficients.
@group(0) @binding(6) var<storage, read> params: array<real>;
@group(0) @binding(7) var<uniform> op: Op;

const WORKGROUP: u32 = 64u;
// Dispatches past 65 535 workgroups spread over y.
fn index(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return gid.x + gid.y * groups.x * WORKGROUP;
}

fn point(vector: u32, n: u32) -> vec3<real> {
    let o = 3u * (NODES * vector + n);
    return vec3<real>(vecs[o], vecs[o + 1u], vecs[o + 2u]);
}

// Hookean spring (thesis eq. 67) or string, tension only beyond its
// compressive tolerance (thesis eq. 3): k δ e on the first node.
fn spring(s: u32, x: u32) -> vec3<real> {
    let d = point(x, ends[2u * s + 1u]) - point(x, ends[2u * s]);
    let l = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    let k = elements[4u * s];
    let rest = elements[4u * s + 1u];
    var stretch = l - rest;
    if elements[4u * s + 3u] != 0.0 {
        stretch = max(l - rest - elements[4u * s + 2u], 0.0);
    }
    var per_length: real = 0.0;
    if l > 0.0 {
        per_length = k * stretch / l;
    }
    return d * per_length;
}

// Viscous damper along a spring: thesis eq. (68) (DAMPING_LAW 0, the whole
// relative velocity) or dissertation eq. (2.38) (1, along the spring); idle
// below its slack length.
fn damper(k: u32, x: u32, v: u32) -> vec3<real> {
    let e0 = ends[2u * (SPRINGS + k)];
    let e1 = ends[2u * (SPRINGS + k) + 1u];
    let d = point(x, e1) - point(x, e0);
    let l = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    let c = elements[4u * (SPRINGS + k)];
    if !(l > elements[4u * (SPRINGS + k) + 1u] && l > 0.0) {
        return vec3<real>(0.0, 0.0, 0.0);
    }
    let dv = point(v, e1) - point(v, e0);
    if DAMPING_LAW == 0u {
        return dv * c;
    }
    let e = d / l;
    return e * (c * (e.x * dv.x + e.y * dv.y + e.z * dv.z));
}

@compute @workgroup_size(64)
fn element_slots(@builtin(global_invocation_id) gid: vec3<u32>,
                 @builtin(num_workgroups) groups: vec3<u32>) {
    let k = index(gid, groups);
    if k >= SPRINGS + DAMPERS {
        return;
    }
    var f: vec3<real>;
    if k < SPRINGS {
        f = spring(k, op.a);
    } else {
        f = damper(k - SPRINGS, op.a, op.b);
    }
    slots[3u * k] = f.x;
    slots[3u * k + 1u] = f.y;
    slots[3u * k + 2u] = f.z;
}

@compute @workgroup_size(64)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>,
          @builtin(num_workgroups) groups: vec3<u32>) {
    let n = index(gid, groups);
    if n >= NODES {
        return;
    }
    let m = nodes[2u * n];
    var sum = vec3<real>(params[0] * m, params[1] * m, params[2] * m);
    for (var e = assembly[n]; e < assembly[n + 1u]; e++) {
        let entry = assembly[NODES + 1u + e];
        let o = 3u * (entry >> 1u);
        let s = vec3<real>(slots[o], slots[o + 1u], slots[o + 2u]);
        if (entry & 1u) == 0u {
            sum += s;
        } else {
            sum -= s;
        }
    }
    let o = 3u * (NODES * op.out + n);
    vecs[o] = sum.x;
    vecs[o + 1u] = sum.y;
    vecs[o + 2u] = sum.z;
}

@compute @workgroup_size(64)
fn combine(@builtin(global_invocation_id) gid: vec3<u32>,
           @builtin(num_workgroups) groups: vec3<u32>) {
    let i = index(gid, groups);
    if i >= 3u * NODES {
        return;
    }
    let c = params[3u + (op.coef >> 1u)];
    var step = c * vecs[3u * NODES * op.b + i];
    if (op.coef & 1u) != 0u {
        step = step * nodes[2u * (i / 3u) + 1u];
    }
    vecs[3u * NODES * op.out + i] = vecs[3u * NODES * op.a + i] + step;
}
