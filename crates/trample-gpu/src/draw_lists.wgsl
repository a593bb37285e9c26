// Draw lists for a renderer drawing straight from the GPU path's buffers
// (DESIGN §7–8; `trample-render`'s `Renderer::encode_gpu`): one thread per
// cell of a visible patch appends its blades (Geometry level) or its
// billboard (Billboard level) to the instance lists a renderer draws with
// indirect draws, as `trample-render`'s `BladePass::prepare` and
// `BillboardPass::prepare` do on the CPU. Nothing is read back.
//
// Blade instances (global blade, debug colour) of chunk k are at
// `blade_instances[first blade of k + slot]`, `slot` < its count; one
// `DrawIndirectArgs` per chunk, then one for the billboards.

// Layout-compatible with `GpuDrawParams` in draw_lists.rs.
struct DrawParams {
    // cells, cells per patch, cells per chunk (all but the last), chunks
    counts: vec4<u32>,
    // blade vertices, billboard vertices, classes view (1) or not (0),
    // billboard debug colour (RGBA8)
    draw: vec4<u32>,
    // billboard half width (m), drawn blades per listed blade (≥ 1; 0
    // reads as 1), near blend band (m: billboard cells nearer than
    // geometry_m + this list their blades too), unused
    size: vec4<f32>,
    // debug colours (RGBA8): DBG this step, DBG earlier, PBG earlier, untouched
    palette: vec4<u32>,
    // PBG this step: rgb at generation 1, w: fade per generation
    pbg: vec4<f32>,
}

// Layout-compatible with `BillboardInstance` in trample-render.
struct Billboard {
    base: vec4<f32>,
    top: vec4<f32>,
    extra: vec4<u32>,
}

@group(0) @binding(0) var<uniform> params: StepParams;
@group(0) @binding(1) var<uniform> draw: DrawParams;
@group(0) @binding(2) var<storage, read> cell_state: array<u32>;
@group(0) @binding(3) var<storage, read> cell_rest: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> slope: array<vec4<f32>>;
// 1 per visible patch.
@group(0) @binding(5) var<storage, read> visible: array<u32>;
@group(0) @binding(6) var<storage, read> generation: array<u32>;
@group(0) @binding(7) var<storage, read> blade_class: array<u32>;
@group(0) @binding(8) var<storage, read_write> blade_instances: array<vec2<u32>>;
@group(0) @binding(9) var<storage, read_write> billboards: array<Billboard>;
// Per chunk its blade count, then the billboard count.
@group(0) @binding(10) var<storage, read_write> counts: array<atomic<u32>>;
// DrawIndirectArgs (vertex count, instance count, first vertex, first
// instance) per chunk, then the billboards'.
@group(0) @binding(11) var<storage, read_write> args: array<u32>;
@group(0) @binding(12) var<storage, read> ground: array<f32>;

const DRAW_GEOMETRY: u32 = 0u;
const DRAW_BILLBOARD: u32 = 1u;

// trample-render's `class_colour`.
fn class_colour(b: u32) -> u32 {
    let g = generation[b];
    if g == 0u {
        return draw.palette.x;
    }
    if g != NO_GENERATION {
        let fade = max(1.0 - draw.pbg.w * f32(g - 1u), 0.3);
        return pack4x8unorm(vec4<f32>(draw.pbg.xyz * fade, 1.0));
    }
    let k = blade_class[b] & 0xffu;
    if k == 1u {
        return draw.palette.y;
    }
    if k == 2u {
        return draw.palette.z;
    }
    return draw.palette.w;
}

@compute @workgroup_size(64)
fn list_cells(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let c = gid.x + gid.y * groups.x * 64u;
    if c >= draw.counts.x || visible[c / max(draw.counts.y, 1u)] == 0u {
        return;
    }
    let level = cell_state[c] & 3u;
    // The near blend band (trample-render's `BladePass::prepare`): a
    // billboard cell this near lists its blades as well as its billboard.
    let to_eye = cell_rest[2u * c].xyz - params.eye.xyz;
    let reach = params.eye.w + draw.size.z;
    let in_band = level == DRAW_BILLBOARD && draw.size.z > 0.0 && dot(to_eye, to_eye) < reach * reach;
    if level == DRAW_GEOMETRY || in_band {
        let bpc = params.cells.y;
        let chunk = c / max(draw.counts.z, 1u);
        let slot = atomicAdd(&counts[chunk], bpc);
        let first = chunk * draw.counts.z * bpc;
        for (var j = 0u; j < bpc; j++) {
            let b = c * bpc + j;
            var colour = 0u;
            if draw.draw.z == 1u {
                colour = class_colour(b);
                // trample-render's `band_colour`: untouched blades of a
                // billboard cell show the billboards' colour.
                if in_band && colour == draw.palette.w {
                    colour = draw.draw.w;
                }
            }
            blade_instances[first + slot + j] = vec2<u32>(b, colour);
        }
    }
    if level == DRAW_BILLBOARD {
        let base = cell_rest[2u * c].xyz;
        let top = billboard_top(base, slope[c].xyz, cell_rest[2u * c].w);
        let slot = atomicAdd(&counts[draw.counts.w], 1u);
        billboards[slot] = Billboard(
            vec4<f32>(base, draw.size.x),
            vec4<f32>(top - base, 0.0),
            vec4<u32>(draw.draw.w, c, 0u, 0u),
        );
    }
}

// One thread per chunk and one for the billboards.
@compute @workgroup_size(64)
fn list_args(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x;
    if k > draw.counts.w {
        return;
    }
    var verts = draw.draw.x;
    if k == draw.counts.w {
        verts = draw.draw.y;
    }
    args[4u * k] = verts;
    // Blade chunks: `size.y` drawn copies of each listed blade (the
    // renderer's render density, at least 1).
    var copies = max(u32(draw.size.y), 1u);
    if k == draw.counts.w {
        copies = 1u;
    }
    args[4u * k + 1u] = atomicLoad(&counts[k]) * copies;
    args[4u * k + 2u] = 0u;
    args[4u * k + 3u] = 0u;
}
