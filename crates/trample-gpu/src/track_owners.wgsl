// Track owners renumbered after bodies left a running simulation (issue
// 14): the GPU twin of `Simulation::remove_body`'s renumbering
// (`trample::step::bodies::renumbered_owners`). Owner o, bits 8–15 of a
// blade's class word, becomes table[o]; the class itself (bits 0–7) stays.

struct Renumber {
    // Blades, workgroups along x, unused ×2.
    counts: vec4<u32>,
    // The new number of old owner o: component o % 4 of entry o / 4.
    table: array<vec4<u32>, 64>,
}

@group(0) @binding(0) var<uniform> renumber: Renumber;
@group(0) @binding(1) var<storage, read_write> blade_class: array<u32>;

@compute @workgroup_size(64)
fn renumber_owners(@builtin(global_invocation_id) gid: vec3<u32>) {
    let b = gid.x + gid.y * renumber.counts.y * 64u;
    if b >= renumber.counts.x {
        return;
    }
    let c = blade_class[b];
    let o = (c >> 8u) & 0xffu;
    let n = renumber.table[o / 4u][o % 4u];
    blade_class[b] = (c & 0xffff00ffu) | (n << 8u);
}
