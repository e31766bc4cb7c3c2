// The projection: the divergence, the pressure operator and its
// multigrid, the gradient and the pressure updates, the Courant number
// (flow.wgsl's header holds the bindings and the sides).

// ---- The projection --------------------------------------------------------

// o0 ← −∇·u/Δt per cell (fluid-proc's faces::divergence).
@compute @workgroup_size(256)
fn divergence(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count {
        return;
    }
    let c = vec3<i32>(cell_coords(NC, t));
    var div: real = 0.0;
    for (var d = 0u; d < 3u; d++) {
        if NC[d] > 1u {
            div += (rd(at(d, c + unit(d))) - rd(at(d, c))) * s[INV_H + d];
        }
    }
    wr(op.o0 + t, div * (-1.0 / s[DT]));
}

// The 7-point stencil of A = −∇²ₕ at cell t of level l, x at `off`
// (fluid-proc's laplacian.rs): its diagonal and the weighted sum of the
// neighbours, A x = diagonal·x − sum. A side of given velocity drops its
// term, an outflow (φ = 0 on the face) doubles it, a periodic side wraps.
fn stencil(l: u32, off: u32, t: u32) -> vec2<real> {
    let n = LEVEL_N[l];
    let c = cell_coords(n, t);
    var diag: real = 0.0;
    var sum: real = 0.0;
    for (var d = 0u; d < 3u; d++) {
        if n[d] == 1u {
            continue;
        }
        let w = s[LEVEL_H2 + 3u * l + d];
        for (var up = 0u; up < 2u; up++) {
            let at_side = select(c[d] == 0u, c[d] + 1u == n[d], up == 1u);
            var m = c;
            if !at_side {
                m[d] = select(c[d] - 1u, c[d] + 1u, up == 1u);
            } else {
                let side = SIDE[2u * d + up];
                if side == OUTFLOW {
                    diag += 2.0 * w;
                    continue;
                }
                if side != PERIODIC {
                    continue;
                }
                m[d] = select(n[d] - 1u, 0u, up == 1u);
            }
            diag += w;
            sum += w * rd(off + cell_index(n, m));
        }
    }
    return vec2<real>(diag, sum);
}

// (A x)_c at cell t of level l, x at `off`.
fn poisson(l: u32, off: u32, t: u32) -> real {
    let a = stencil(l, off, t);
    return a.x * rd(off + t) - a.y;
}

// On level op.comp: o1 ← A x (kind 0) or b − A x (kind 1), x at o0, b at o2.
@compute @workgroup_size(256)
fn poisson_apply(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count || skipped() {
        return;
    }
    let ax = poisson(op.comp, op.o0, t);
    if op.kind == 1u {
        wr(op.o1 + t, rd(op.o2 + t) - ax);
    } else {
        wr(op.o1 + t, ax);
    }
}

// On how many axes cell c of level l is the last cell of an odd periodic
// axis, whose neighbour across the wrap has its colour (spec.rs's
// `seam_phase`): a colour is swept phase by phase, as fluid-proc sweeps
// it in order, so that no two cells of one dispatch touch.
fn seam_phase(l: u32, c: vec3<u32>) -> u32 {
    let n = LEVEL_N[l];
    var phase = 0u;
    for (var d = 0u; d < 3u; d++) {
        let odd = n[d] % 2u == 1u && n[d] >= 3u;
        if SIDE[2u * d] == PERIODIC && odd && c[d] + 1u == n[d] {
            phase += 1u;
        }
    }
    return phase;
}

// One Gauss–Seidel update of cell t of level l for A x = b (x at xo, b at
// bo) where it has colour `colour` ((i + j + k) mod 2) and seam phase
// `phase`.
fn relax(l: u32, bo: u32, xo: u32, t: u32, colour: u32, phase: u32) {
    let c = cell_coords(LEVEL_N[l], t);
    if (c.x + c.y + c.z) % 2u != colour || seam_phase(l, c) != phase {
        return;
    }
    let a = stencil(l, xo, t);
    if a.x != 0.0 {
        // A x = d·x − Σ: x ← (b + Σ)/d, as fluid-proc's Gauss–Seidel.
        wr(xo + t, (rd(bo + t) + a.y) / a.x);
    }
}

// One seam phase (op.kind) of one colour's sweep (op.aux) of level
// op.comp: b at o0, x at o1.
@compute @workgroup_size(256)
fn sweep(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count || skipped() {
        return;
    }
    relax(op.comp, op.o0, op.o1, t, op.aux, op.kind);
}

// Whether level l halves along d into level l + 1.
fn halves(l: u32, d: u32) -> bool {
    return LEVEL_N[l + 1u][d] < LEVEL_N[l][d];
}

// Level op.comp's residual (o0) restricted to level op.comp + 1's b (o1):
// each coarse cell the mean of its children, in ascending order.
@compute @workgroup_size(256)
fn restriction(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count || skipped() {
        return;
    }
    let l = op.comp;
    let fine = LEVEL_N[l];
    let p = cell_coords(LEVEL_N[l + 1u], t);
    var kids = vec3<u32>(1u, 1u, 1u);
    var first = p;
    var share: real = 1.0;
    for (var d = 0u; d < 3u; d++) {
        if halves(l, d) {
            kids[d] = 2u;
            first[d] = 2u * p[d];
            share *= 0.5;
        }
    }
    var sum: real = 0.0;
    for (var k = 0u; k < kids.z; k++) {
        for (var j = 0u; j < kids.y; j++) {
            for (var i = 0u; i < kids.x; i++) {
                sum += rd(op.o0 + cell_index(fine, first + vec3<u32>(i, j, k))) * share;
            }
        }
    }
    wr(op.o1 + t, sum);
}

// Level op.comp's x (o0) += its parents' correction on level op.comp + 1 (o1).
@compute @workgroup_size(256)
fn prolongation(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count || skipped() {
        return;
    }
    let l = op.comp;
    var c = cell_coords(LEVEL_N[l], t);
    for (var d = 0u; d < 3u; d++) {
        if halves(l, d) {
            c[d] /= 2u;
        }
    }
    wr(op.o0 + t, rd(op.o0 + t) + (rd(op.o1 + cell_index(LEVEL_N[l + 1u], c))));
}

// The coarsest level op.comp (b at o0, x at o1) on one workgroup: x from
// zero by COARSEST_SWEEPS symmetric red–black sweeps, each colour in its
// op.kind seam phases, mean-free where A is singular (fluid-proc's
// multigrid.rs).
@compute @workgroup_size(256)
fn coarsest(@builtin(local_invocation_index) local: u32) {
    if workgroup_skips(local) {
        return;
    }
    let l = op.comp;
    let n = op.count;
    for (var t = local; t < n; t += WG) {
        wr(op.o1 + t, 0.0);
    }
    storageBarrier();
    for (var sweep = 0u; sweep < 4u * COARSEST_SWEEPS; sweep++) {
        // Red, black, black, red.
        let k = sweep % 4u;
        let colour = select(1u, 0u, k == 0u || k == 3u);
        for (var phase = 0u; phase < op.kind; phase++) {
            for (var t = local; t < n; t += WG) {
                relax(l, op.o0, op.o1, t, colour, phase);
            }
            storageBarrier();
            workgroupBarrier();
        }
    }
    if !SINGULAR {
        return;
    }
    var v: real = 0.0;
    for (var t = local; t < n; t += WG) {
        v += rd(op.o1 + t);
    }
    shared_sum[local] = v;
    combine_shared(local, false);
    let mean = shared_sum[0] / real(n);
    for (var t = local; t < n; t += WG) {
        wr(op.o1 + t, rd(op.o1 + t) - (mean));
    }
}

// u_d −= Δt ∂φ/∂x_d on every face of component op.comp (the op's box).
@compute @workgroup_size(256)
fn gradient(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= box_size() || skipped() {
        return;
    }
    let pc = box_coords(t);
    let q = vec3<i32>(pc) - vec3<i32>(GH);
    let d = op.comp;
    wr(U_OFF[d] + box_index(pc), rd(U_OFF[d] + box_index(pc)) - (s[DT] * face_gradient(PHI_OFF, d, q)));
}

// Eq. (3.20) with A = −∇²: q ← q + φ + (νΔt/2)Aφ per cell.
@compute @workgroup_size(256)
fn pressure_update(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count || skipped() {
        return;
    }
    wr(Q_OFF + t, rd(Q_OFF + t) + (rd(PHI_OFF + t) + s[ALPHA] * poisson(0u, PHI_OFF, t)));
}

// o0 ← Σ_a |u_a|/h_a per cell, u_a the mean of the cell's two a-faces: the
// Courant number of a unit step (fluid-proc's `Incompressible::courant`).
@compute @workgroup_size(256)
fn courant(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count || skipped() {
        return;
    }
    let c = vec3<i32>(cell_coords(NC, t));
    var sum: real = 0.0;
    for (var a = 0u; a < 3u; a++) {
        if NC[a] > 1u {
            sum += abs(0.5 * (rd(at(a, c)) + rd(at(a, c + unit(a))))) * s[INV_H + a];
        }
    }
    wr(op.o0 + t, sum);
}

