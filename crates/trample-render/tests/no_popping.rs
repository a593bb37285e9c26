//! No popping (issue 3, DESIGN §6): a ball leaves a track; then a camera
//! backs away from it, so that the track's cells cross the geometry → billboard boundary while we
//! watch. The mean pixel change between consecutive frames in the band that
//! changes level must stay within [`MAX_BAND_FACTOR`] times the change
//! elsewhere in the frame (where the change comes from the camera's motion
//! alone). With the transition rules (Eq. 9–13) switched off the billboards
//! of trampled cells stand up at rest the moment their cell leaves geometry:
//! the same measurement must then exceed the factor, so the test can fail
//! (drawn with the paper's hard switch between levels: the renderer's
//! blend band hides that pop, which a test of its own checks).
//!
//! The band: the pixel blocks where the cells whose level changed since the
//! last frame are drawn (each cell projected from its base up).
//! Runs on the adapter of `WGPU_BACKEND`; no adapter = failure.

mod common;

use glam::Vec3;
use trample::Simulation;
use trample::scene::Scene;
use trample_render::{DebugView, Renderer};

const W: u32 = 200;
const H: u32 = 152;
const DT: f32 = 1.0 / 60.0;
/// Steps before the camera starts moving: the ball has left its track and
/// the field.
const SETTLE_STEPS: u32 = 100;
/// Steps between two rendered frames.
const STEPS_PER_FRAME: u32 = 1;
/// Rendered frames while the camera backs away (1 m, 1.25 cm per frame).
const FRAMES: u32 = 80;
/// Tip displacement that makes a cell part of the track, metres.
const TRAMPLED_M: f32 = 0.25;
/// Side of the pixel blocks compared, pixels: the blocks' mean colours are
/// compared, so the grass's fine texture sliding under a moving camera
/// averages out while a whole cell that changes its look does not.
const BLOCK: u32 = 4;

/// Largest allowed ratio of the mean change in the band to the mean change
/// elsewhere. Measured on llvmpipe (GL), 2026-11-21: 1.45 with the
/// transition rules, 1.80 without them; the bound sits between the two with
/// about 10 % on either side. Rendering on one driver is deterministic, so
/// the figures repeat exactly there. Re-measured 2026-11-23 after the
/// tighter OBB trees (issue 16) changed the ball's boxes and so its track:
/// 1.62 with the rules, 1.78 without (the paper's mode), 1.63 with the
/// track everywhere backing away and 1.53 coming closer; the bound moved
/// from 1.6 to 1.7 to sit between the two again (about 5 % on either side).
/// 2026-11-25, with the blend bands and coverage-keeping billboard mips
/// (issue 15 item 1): hard switch 1.59 with the rules, 1.75 without; with
/// the blend band 1.14 (paper's mode, rules off), 1.13 (track everywhere,
/// rules off), 1.12 (camera approaching). Then the ambient occlusion of
/// issue 15 item 3 (roots and billboard bases darker: the frame's own
/// change grows, so the band's share drops): hard switch 1.54 with the
/// rules, 1.67 without; the bound moved from 1.7 to 1.6 to sit between the
/// two again (about 4 % on either side); with the blend band 1.21 (paper's
/// mode, rules off), 1.21 (track everywhere, rules off), 1.22 (camera
/// approaching).
const MAX_BAND_FACTOR: f64 = 1.6;

/// A 4.8 m field; a 0.5 m ball rolls across it along x at z = 0.6 in
/// 1.5 s; the camera waits, then backs away along +z looking at a fixed
/// point, so the geometry disc around it slides over the track.
fn scene(approach: bool) -> Simulation {
    let (near, far) = if approach { (2.6, 1.6) } else { (1.6, 2.6) };
    let toml = format!(
        r#"
[field]
patches = [6, 6]
cells_per_patch = 8
blades_per_cell = 6
cell_size_m = 0.1
[lod]
geometry_m = 1.8
billboard_m = 30.0
[sim]
recovery_s = inf
[camera]
path = {{ kind = "keyframes", keys = [
  {{ t_s = 0.0, position = [0.0, 1.0, {near}] }},
  {{ t_s = {start}, position = [0.0, 1.0, {near}] }},
  {{ t_s = {end}, position = [0.0, 1.0, {far}] }},
] }}
look_at = {{ kind = "point", at = [0.0, 0.0, -1.0] }}
aspect = {aspect}
[[objects]]
name = "ball"
shape = {{ kind = "sphere", radius_m = 0.5 }}
orientation = "rolling"
path = {{ kind = "line", from = [-3.5, 0.5, 0.6], to = [6.0, 0.5, 0.6], duration_s = 1.5 }}
"#,
        start = SETTLE_STEPS as f32 * DT,
        end = (SETTLE_STEPS + STEPS_PER_FRAME * FRAMES) as f32 * DT,
        aspect = W as f32 / H as f32
    );
    Scene::parse(&toml, "no_popping.toml", std::path::Path::new("."))
        .unwrap()
        .build()
        .unwrap()
}

/// Mean colour of each [`BLOCK`]² block, row by row.
fn block_means(img: &image::RgbaImage) -> Vec<[f64; 3]> {
    let (bw, bh) = (W / BLOCK, H / BLOCK);
    let mut out = vec![[0.0; 3]; (bw * bh) as usize];
    for (x, y, p) in img.enumerate_pixels() {
        let (bx, by) = (x / BLOCK, y / BLOCK);
        if bx < bw && by < bh {
            let m = &mut out[(by * bw + bx) as usize];
            for c in 0..3 {
                m[c] += f64::from(p[c]) / f64::from(BLOCK * BLOCK);
            }
        }
    }
    out
}

/// True when a blade of cell `c` has its tip more than [`TRAMPLED_M`] from
/// its rest position: a cell of the track. Blades are the same in both runs
/// up to the moment their cell leaves geometry (the rules act on the
/// billboard then), so both runs pick the same cells.
fn trampled(sim: &Simulation, c: usize) -> bool {
    let bl = &sim.field.blades;
    let (n, bpc) = (bl.segments, sim.field.layout.blades_per_cell as usize);
    (c * bpc..(c + 1) * bpc).any(|b| bl.vertex(b, n).distance(bl.rest_vertex(b, n)) > TRAMPLED_M)
}

/// Marks the blocks where the cells that changed level are drawn: the
/// projection of each cell from its base up to half its blade height, in
/// `sim`'s current view.
fn band_blocks(sim: &Simulation, changed: &[usize], band: &mut [bool]) {
    let view_proj = sim.view.proj() * sim.view.view();
    let (bw, bh) = (W / BLOCK, H / BLOCK);
    for &c in changed {
        let base = sim.field.cells.base[c];
        for k in 0..=4 {
            let p = base + Vec3::Y * (sim.field.cells.height[c] * 0.125 * k as f32);
            let clip = view_proj * p.extend(1.0);
            if clip.w <= 0.0 {
                continue;
            }
            let x = (clip.x / clip.w * 0.5 + 0.5) * W as f32;
            let y = (1.0 - clip.y / clip.w) * 0.5 * H as f32;
            if x >= 0.0 && y >= 0.0 {
                let (bx, by) = (x as u32 / BLOCK, y as u32 / BLOCK);
                if bx < bw && by < bh {
                    band[(by * bw + bx) as usize] = true;
                }
            }
        }
    }
}

/// What one camera move measured.
#[derive(Debug)]
struct Popping {
    /// Mean change in the band / mean change elsewhere.
    factor: f64,
    /// Band blocks over all frame pairs.
    band_blocks: usize,
    /// Cells that changed level while the frames were taken.
    transitions: u32,
}

/// Runs the scene with the transition rules on or off and measures;
/// `bands`: the renderer's blend bands between levels (issue 15 item 1;
/// off: the paper's hard switch).
fn measure(transitions: bool, track_everywhere: bool, approach: bool, bands: bool) -> Popping {
    let gpu = trample_render::headless::create_device()
        .unwrap_or_else(|e| panic!("the no-popping test needs an adapter: {e}"));
    let mut sim = scene(approach);
    sim.params.transitions = transitions;
    sim.params.track_everywhere = track_everywhere;
    for _ in 0..SETTLE_STEPS {
        sim.step(DT).unwrap();
    }
    assert!(
        sim.blades_away_from_rest() > 1000,
        "the ball must have bent a track: {} blades bent",
        sim.blades_away_from_rest()
    );
    let renderer = |debug| {
        let params = common::test_params(&gpu, W, H, debug);
        let params = if bands {
            params
        } else {
            params.without_blend_bands()
        };
        Renderer::new(&gpu.device, &gpu.queue, &sim, params).unwrap()
    };
    let dump = std::env::var_os("TRAMPLE_DUMP_FRAMES");
    let mut shaded = renderer(DebugView::None);
    // The classes view is for a person looking at the dumped frames.
    let mut classes = dump.as_ref().map(|_| renderer(DebugView::Classes));
    let blocks = ((W / BLOCK) * (H / BLOCK)) as usize;
    // Per frame: the shaded image, the classes view (for people), and the
    // band: blocks showing a cell whose level changed since the last frame.
    let mut frames = Vec::new();
    let mut changed = 0;
    for i in 0..=FRAMES {
        let mut band = vec![false; blocks];
        if i > 0 {
            let before = sim.field.cells.lod.clone();
            for _ in 0..STEPS_PER_FRAME {
                changed += sim.step(DT).unwrap().transitions;
            }
            let cells: Vec<usize> = (0..before.len())
                .filter(|&c| before[c] != sim.field.cells.lod[c] && trampled(&sim, c))
                .collect();
            band_blocks(&sim, &cells, &mut band);
        }
        frames.push((
            shaded.render(&gpu.device, &gpu.queue, &sim).unwrap(),
            classes
                .as_mut()
                .map(|r| r.render(&gpu.device, &gpu.queue, &sim).unwrap()),
            band,
        ));
    }
    if let Some(dir) = dump {
        // For a person looking into a failure: the frames as PNGs.
        let dir = std::path::Path::new(&dir);
        std::fs::create_dir_all(dir).unwrap();
        let tag = if transitions { "on" } else { "off" };
        for (i, (s, c, _)) in frames.iter().enumerate() {
            s.save(dir.join(format!("{tag}-{i:02}-shaded.png")))
                .unwrap();
            if let Some(c) = c {
                c.save(dir.join(format!("{tag}-{i:02}-classes.png")))
                    .unwrap();
            }
        }
    }
    let (mut band, mut band_n, mut other, mut other_n) = (0.0, 0usize, 0.0, 0usize);
    for pair in frames.windows(2) {
        let ((s0, _, _), (s1, _, in_band)) = (&pair[0], &pair[1]);
        let (m0, m1) = (block_means(s0), block_means(s1));
        for ((a, b), &in_band) in m0.iter().zip(&m1).zip(in_band) {
            let change = (0..3).map(|c| (a[c] - b[c]).abs()).sum::<f64>() / 3.0;
            if in_band {
                band += change;
                band_n += 1;
            } else {
                other += change;
                other_n += 1;
            }
        }
    }
    assert!(
        band_n > 0 && other_n > 0,
        "band {band_n}, elsewhere {other_n}"
    );
    Popping {
        factor: (band / band_n as f64) / (other / other_n as f64),
        band_blocks: band_n,
        transitions: changed,
    }
}

#[test]
fn cells_changing_level_do_not_pop_and_do_without_the_transition_rules() {
    // The paper's mode: only geometric cells are simulated, so the rules
    // (Eq. 9-13) are what carries a track across the boundary; drawn with
    // the paper's hard switch between levels (no blend band, which would
    // hide a pop: tested below).
    let on = measure(true, false, false, false);
    let off = measure(false, false, false, false);
    eprintln!("no popping: transitions on {on:?}; off {off:?}");
    for p in [&on, &off] {
        assert!(
            p.transitions > 200 && p.band_blocks > 100,
            "the camera must move cells across the boundary in view: {p:?}"
        );
    }
    assert!(
        on.factor <= MAX_BAND_FACTOR,
        "with the transition rules the band changes {:.2}× as much as the rest of the frame (max {MAX_BAND_FACTOR}): {on:?}",
        on.factor
    );
    assert!(
        off.factor > MAX_BAND_FACTOR,
        "without the transition rules the band must pop (factor > {MAX_BAND_FACTOR}), got {:.2}: {off:?}",
        off.factor
    );
}

/// Ours (`track_everywhere`, the default): every touched blade is simulated
/// whatever its level and billboards follow their blades, so a cell that
/// changes level shows the same track with or without the rules.
#[test]
fn with_the_track_everywhere_cells_do_not_pop_even_without_the_rules() {
    let off = measure(false, true, false, true);
    eprintln!("no popping, track everywhere, rules off: {off:?}");
    assert!(
        off.transitions > 200 && off.band_blocks > 100,
        "the camera must move cells across the boundary in view: {off:?}"
    );
    assert!(
        off.factor <= MAX_BAND_FACTOR,
        "with the track everywhere the band changes {:.2}× as much as the rest of the frame (max {MAX_BAND_FACTOR}): {off:?}",
        off.factor
    );
}

/// The other direction: the camera comes closer, so track cells turn from
/// billboards into blades. With the track everywhere the blades are already
/// bent as made (no Eq. 13 guess), so the band changes no more than the
/// rest of the frame. (The paper's mode has no blades to show here: its
/// track in billboard cells lives in the billboards' slopes only.)
#[test]
fn cells_coming_closer_do_not_pop() {
    let ours = measure(true, true, true, true);
    eprintln!("no popping, camera approaching, track everywhere: {ours:?}");
    assert!(
        ours.transitions > 200 && ours.band_blocks > 100,
        "the camera must move cells across the boundary in view: {ours:?}"
    );
    assert!(
        ours.factor <= MAX_BAND_FACTOR,
        "camera approaching: the band changes {:.2}× as much as the rest of the frame (max {MAX_BAND_FACTOR}): {ours:?}",
        ours.factor
    );
}

/// The renderer's near blend band (issue 15 item 1) draws the blades of
/// billboard cells near the boundary, thinning out while the billboards
/// fade in: even in the paper's mode with the transition rules off (which
/// pops with the hard switch, above) a cell that leaves geometry does not
/// pop there.
#[test]
fn the_blend_band_does_not_pop() {
    let off = measure(false, false, false, true);
    eprintln!("no popping, paper's mode, rules off, blend band: {off:?}");
    assert!(
        off.transitions > 200 && off.band_blocks > 100,
        "the camera must move cells across the boundary in view: {off:?}"
    );
    assert!(
        off.factor <= MAX_BAND_FACTOR,
        "with the blend band the band changes {:.2}× as much as the rest of the frame (max {MAX_BAND_FACTOR}): {off:?}",
        off.factor
    );
}
