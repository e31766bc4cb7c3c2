// The flow's monitors on the device (fluid-proc's `Incompressible`
// kinetic_energy, momentum, max_divergence and max_change), so that a
// window's end need not bring the velocities back to the host.

// o0 ← per cell: |v|² (kind 0), v_x, v_y, v_z (kinds 1–3), v the mean of
// the cell's two faces along each axis; or |∇·u| (kind 4).
@compute @workgroup_size(256)
fn cell_monitor(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= op.count {
        return;
    }
    let c = vec3<i32>(cell_coords(NC, t));
    var v = vec3<real>(0.0, 0.0, 0.0);
    var div: real = 0.0;
    for (var a = 0u; a < 3u; a++) {
        if NC[a] > 1u {
            let lo = rd(at(a, c));
            let hi = rd(at(a, c + unit(a)));
            v[a] = 0.5 * (lo + hi);
            div += (hi - lo) * s[INV_H + a];
        }
    }
    var out: real;
    switch op.kind {
        case 0u: {
            out = dot(v, v);
        }
        case 4u: {
            out = abs(div);
        }
        default: {
            out = v[op.kind - 1u];
        }
    }
    wr(op.o0 + t, out);
}

// o1 ← |u − u at the window's start| on every face of component op.comp
// (its box), u at o0 and the start at o2.
@compute @workgroup_size(256)
fn face_change(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = thread(gid, groups);
    if t >= box_size() {
        return;
    }
    let rel = box_index(box_coords(t));
    wr(op.o1 + rel, abs(rd(op.o0 + rel) - rd(op.o2 + rel)));
}
