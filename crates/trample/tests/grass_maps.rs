//! Grass maps (issue 14, item 6): density (0 = no grass), height and tint
//! per position, from images in a scene file or closures in code. Blades
//! grow only where the density is above 0 (none on `garden.toml`'s mown
//! path or its bare patch), heights follow the height map, tints the tint
//! map, nothing collides with or propagates through the blades left out,
//! and the memory estimate follows the density.
//!
//! This file also draws `scenes/garden/*.png` (the maps of `garden.toml`):
//! `UPDATE_MAPS=1 cargo test -p trample --test grass_maps` rewrites them;
//! without it, the test checks the committed images are what it draws.

use std::path::{Path, PathBuf};
use trample::builder::SimulationBuilder;
use trample::field::generate::growing_blades;
use trample::field::{FieldParams, GrassMap, GrassMaps, LodParams};
use trample::recovery::RECOVERY_CLOCK_BYTES;
use trample::scene::Scene;
use trample::step::SimParams;
use trample::{BodyBuilder, Simulation};

// ---------------------------------------------------------------- the garden

/// Side of `garden.toml`'s field, metres (8 patches of 32 cells of 0.1 m).
const GARDEN_M: f32 = 25.6;
/// Pixels along each side of the garden's maps (0.2 m a pixel).
const MAP_PX: u32 = 129;
/// Half width of the mown path, metres.
const PATH_HALF_M: f32 = 0.7;
/// Centre and radius of the bare patch, metres.
const BARE: ([f32; 2], f32) = ([6.0, -6.0], 2.5);
/// `height_range` of `garden.toml`: white is 1.5 × the blade height.
const HEIGHT_MAX: f32 = 1.5;

/// Centre line of the path: an S-curve along x.
fn path_z(x: f32) -> f32 {
    3.0 * (x * 0.25).sin()
}

/// Distance from (x, z) to the path's centre line (across it, near enough
/// for a gentle curve).
fn from_path(x: f32, z: f32) -> f32 {
    let slope = 0.75 * (x * 0.25).cos();
    (z - path_z(x)).abs() / (1.0 + slope * slope).sqrt()
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Density: none on the path and the bare patch, full elsewhere, with
/// 30 cm soft edges.
fn garden_density(x: f32, z: f32) -> f32 {
    let path = smoothstep(PATH_HALF_M, PATH_HALF_M + 0.3, from_path(x, z));
    let bare = smoothstep(BARE.1, BARE.1 + 0.3, (x - BARE.0[0]).hypot(z - BARE.0[1]));
    path * bare
}

/// Height factor: a short-cut verge 1 m either side of the path, taller
/// grass towards the (-x, +z) corner.
fn garden_height(x: f32, z: f32) -> f32 {
    let verge = 0.4 + 0.6 * smoothstep(PATH_HALF_M, PATH_HALF_M + 1.0, from_path(x, z));
    let corner = 1.0 + 0.4 * smoothstep(4.0, 10.0, (-x).min(z));
    verge * corner
}

/// Tint: a dry strip in the sun along the -z edge, lush elsewhere, with a
/// slow variation.
fn garden_tint(x: f32, z: f32) -> f32 {
    let dry = smoothstep(-6.0, -9.0, z);
    (0.2 + 0.6 * dry + 0.08 * (x * 0.7).sin() * (z * 0.5).cos()).clamp(0.0, 1.0)
}

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// `f` over the garden as an 8-bit grey image (column i at x, row j at z,
/// as the maps are read), `scale` mapping values to [0, 1].
fn draw(f: fn(f32, f32) -> f32, scale: f32) -> image::GrayImage {
    image::GrayImage::from_fn(MAP_PX, MAP_PX, |i, j| {
        let at = |p: u32| -GARDEN_M * 0.5 + p as f32 / (MAP_PX - 1) as f32 * GARDEN_M;
        let v = (f(at(i), at(j)) / scale).clamp(0.0, 1.0);
        image::Luma([(v * 255.0).round() as u8])
    })
}

#[test]
fn the_garden_maps_are_the_committed_images() {
    let dir = scenes().join("garden");
    for (name, img) in [
        ("density.png", draw(garden_density, 1.0)),
        ("height.png", draw(garden_height, HEIGHT_MAX)),
        ("tint.png", draw(garden_tint, 1.0)),
    ] {
        let path = dir.join(name);
        if std::env::var_os("UPDATE_MAPS").is_some() {
            std::fs::create_dir_all(&dir).unwrap();
            img.save(&path).unwrap();
        }
        let committed = image::open(&path)
            .unwrap_or_else(|e| panic!("{}: {e} (UPDATE_MAPS=1 draws it)", path.display()))
            .into_luma8();
        assert!(committed == img, "{name} differs from what this test draws");
    }
}

#[test]
fn the_garden_grows_no_blade_on_its_path_or_bare_patch() {
    let scene = Scene::load(&scenes().join("garden.toml")).unwrap();
    let sim = scene.build().unwrap();
    let maps = GrassMaps::from_params(
        &scene.file.field.maps,
        scene.file.field.extent_m(),
        &scene.base_dir,
    )
    .unwrap();
    let bl = &sim.field.blades;
    let (mut on_path, mut on_bare, mut meadow, mut meadow_grown) = (0, 0, 0, 0);
    for b in 0..bl.count {
        let r = bl.rest_vertex(b, 0);
        let grown = bl.is_present(b);
        assert!(
            !grown || maps.density_at(r.x, r.z) > 0.0,
            "blade {b} grows at density 0"
        );
        // Inside the path and the patch by more than a pixel's diagonal (the
        // image is sampled bilinearly between 0.2 m pixels).
        if from_path(r.x, r.z) < PATH_HALF_M - 0.3 {
            on_path += 1;
            assert!(
                !grown,
                "blade {b} grows on the mown path at ({}, {})",
                r.x, r.z
            );
        }
        if (r.x - BARE.0[0]).hypot(r.z - BARE.0[1]) < BARE.1 - 0.3 {
            on_bare += 1;
            assert!(!grown, "blade {b} grows on the bare patch");
        }
        if garden_density(r.x, r.z) == 1.0 && maps.density_at(r.x, r.z) >= 0.999 {
            meadow += 1;
            meadow_grown += usize::from(grown);
        }
    }
    assert!(on_path > 1000 && on_bare > 1000, "{on_path} {on_bare}");
    assert_eq!(meadow_grown, meadow, "every meadow blade grows");
    assert_eq!(
        growing_blades(&scene.file.field, &maps) as usize,
        (0..bl.count).filter(|&b| bl.is_present(b)).count()
    );
}

// ---------------------------------------------------------- maps from code

/// 6.4 × 6.4 m, every cell geometric, the given maps.
fn field_with(maps: GrassMaps, blades_per_cell: u32) -> SimulationBuilder {
    SimulationBuilder::new()
        .field(FieldParams {
            patches: [4, 4],
            cells_per_patch: 16,
            blades_per_cell,
            ..FieldParams::default()
        })
        .lod(LodParams {
            geometry_m: 1000.0,
            billboard_m: 2000.0,
        })
        .maps(maps)
}

/// A strip 1 m wide along z at x = 0 with no grass; elsewhere full.
fn strip_density(x: f32, _z: f32) -> f32 {
    if x.abs() < 0.5 { 0.0 } else { 1.0 }
}

fn height_factor(x: f32, z: f32) -> f32 {
    1.0 + 0.15 * x - 0.05 * z
}

fn tint_value(x: f32, z: f32) -> f32 {
    (0.5 + 0.12 * x + 0.03 * z).clamp(0.0, 1.0)
}

fn coded_maps() -> GrassMaps {
    GrassMaps {
        density: GrassMap::function(strip_density),
        height: GrassMap::function(height_factor),
        tint: Some(GrassMap::function(tint_value)),
    }
}

#[test]
fn blades_heights_and_tints_follow_maps_given_as_closures() {
    let sim = field_with(coded_maps(), 2).build().unwrap();
    let p = &sim.field.params;
    let bl = &sim.field.blades;
    let (mut absent, mut grown) = (0, 0);
    for b in 0..bl.count {
        let r = bl.rest_vertex(b, 0);
        if strip_density(r.x, r.z) == 0.0 {
            absent += 1;
            assert!(!bl.is_present(b), "blade {b} grows where the density is 0");
            // Left out: zero height, zero width, every vertex at its root.
            assert_eq!(bl.width[b], 0.0);
            assert!((0..=bl.segments).all(|k| bl.rest_vertex(b, k) == r));
            continue;
        }
        grown += 1;
        assert!(bl.is_present(b));
        let length = bl.seg_len[b] * bl.segments as f32;
        let ratio = length / (p.blade_height_m * height_factor(r.x, r.z));
        assert!(
            (1.0 - p.height_jitter - 1e-5..=1.0 + p.height_jitter + 1e-5).contains(&ratio),
            "blade {b}: length {length} is {ratio} × what the height map asks"
        );
        assert!(
            (bl.tint[b] - tint_value(r.x, r.z)).abs() < 1e-6,
            "blade {b} tint"
        );
    }
    assert!(absent > 500 && grown > 5000, "{absent} {grown}");
    // The heights do follow the map: tall blades where it is high.
    let mean = |sign: f32| {
        let v: Vec<f32> = (0..bl.count)
            .filter(|&b| bl.is_present(b) && bl.rest_vertex(b, 0).x * sign > 2.0)
            .map(|b| bl.seg_len[b])
            .collect();
        v.iter().sum::<f32>() / v.len() as f32
    };
    assert!(
        mean(1.0) > 1.5 * mean(-1.0),
        "{} vs {}",
        mean(1.0),
        mean(-1.0)
    );
}

#[test]
fn nothing_collides_with_or_propagates_through_blades_left_out() {
    // A ball rolls along the bare strip, then across it.
    let mut sim: Simulation = field_with(coded_maps(), 1)
        .body(
            BodyBuilder::sphere("ball", 0.6).path(trample::object::PathParams::Line {
                from: [0.0, 0.6, -3.5],
                to: [0.0, 0.6, 3.5],
                duration_s: 1.5,
            }),
        )
        .build()
        .unwrap();
    sim.run(100).unwrap();
    let bl = &sim.field.blades;
    for b in 0..bl.count {
        if !bl.is_present(b) {
            assert_eq!(
                sim.class[b],
                trample::step::BladeClass::Untouched,
                "blade {b} left out was hit or reached"
            );
            assert!(bl.is_at_rest(b));
        }
    }
    // The strip is 1 m wide and the ball 1.2 m across: it reaches the grass
    // at the strip's edges (and only there).
    assert!(sim.blades_away_from_rest() > 0);
    // Across the strip: the grass on both sides bends, the strip stays bare.
    sim.add_body(
        BodyBuilder::sphere("across", 0.4)
            .at([-2.5, 0.4, 1.0])
            .build()
            .unwrap(),
    );
    let id = sim.bodies.last().unwrap().id;
    let dt = sim.params.dt_s;
    for i in 1..=60 {
        let x = -2.5 + 5.0 * i as f32 / 60.0;
        sim.move_body(id, glam::Vec3::new(x, 0.4, 1.0), glam::Quat::IDENTITY, dt)
            .unwrap();
        sim.step(dt).unwrap();
    }
    let bl = &sim.field.blades;
    let bent_right = (0..bl.count)
        .filter(|&b| bl.rest_vertex(b, 0).x > 1.0 && !bl.is_at_rest(b))
        .count();
    assert!(bent_right > 20, "{bent_right}");
    assert!((0..bl.count).all(|b| bl.is_present(b) || bl.is_at_rest(b)));
}

#[test]
fn the_memory_estimate_follows_the_density() {
    let estimate = |density: f32| {
        let b = field_with(
            GrassMaps {
                density: GrassMap::Constant(density),
                ..GrassMaps::default()
            },
            4,
        );
        let sim = b.build().unwrap();
        let grown = (0..sim.field.blades.count)
            .filter(|&i| sim.field.blades.is_present(i))
            .count();
        // The build keeps the estimate it checked (what `summary.json`
        // reports).
        assert_eq!(sim.memory_estimate_bytes, b.memory_estimate_bytes().ok());
        (
            b.memory_estimate_bytes().unwrap(),
            grown,
            sim.field.blades.count,
        )
    };
    let (full, grown_full, count) = estimate(1.0);
    let (half, grown_half, _) = estimate(0.5);
    let (none, grown_none, _) = estimate(0.0);
    assert_eq!(grown_full, count);
    assert_eq!(grown_none, 0);
    let share = grown_half as f32 / count as f32;
    assert!((share - 0.5).abs() < 0.02, "density 0.5 grew {share}");
    assert!(none < half && half < full, "{none} {half} {full}");
    // The estimate is the formula at the exact count of growing blades,
    // plus the strides' clock of every blade (strides are on by default).
    let p = FieldParams {
        patches: [4, 4],
        cells_per_patch: 16,
        blades_per_cell: 4,
        ..FieldParams::default()
    };
    assert!(SimParams::default().recovery_stride_m > 0.0);
    let clock = count as u64 * RECOVERY_CLOCK_BYTES;
    assert_eq!(full, p.memory_estimate_bytes() + clock);
    assert_eq!(half, p.memory_estimate_bytes_for(grown_half as u64) + clock);
    assert_eq!(none, p.memory_estimate_bytes_for(0) + clock);
    // Without strides there is no clock to count.
    let every_step = field_with(GrassMaps::default(), 4).sim(SimParams {
        recovery_stride_m: 0.0,
        ..SimParams::default()
    });
    assert_eq!(
        every_step.memory_estimate_bytes().unwrap(),
        p.memory_estimate_bytes()
    );
    // Half the grass saves the work memory of the other half: with 4
    // segments, 376 of 576 bytes a blade.
    let saved = (full - half) as f64 / (count - grown_half) as f64;
    assert!((saved - 376.0).abs() < 1.0, "{saved}");
}

// ------------------------------------------------------------ bad map input

/// A PNG whose header says `w`×`h` 16-bit grey pixels, with almost no
/// data: what an image too large to decode looks like to the decoder
/// before it allocates.
fn huge_png_header(w: u32, h: u32) -> Vec<u8> {
    fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
        out.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let start = out.len();
        out.extend_from_slice(kind);
        out.extend_from_slice(data);
        let crc = crc32(&out[start..]);
        out.extend_from_slice(&crc.to_be_bytes());
    }
    fn crc32(bytes: &[u8]) -> u32 {
        let mut c = !0u32;
        for &b in bytes {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 == 1 {
                    0xedb8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&w.to_be_bytes());
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[16, 0, 0, 0, 0]);
    chunk(&mut out, b"IHDR", &ihdr);
    // A stored (uncompressed) zlib stream of one zero byte.
    chunk(
        &mut out,
        b"IDAT",
        &[
            0x78, 0x01, 0x01, 0x01, 0x00, 0xfe, 0xff, 0x00, 0x00, 0x01, 0x00, 0x01,
        ],
    );
    chunk(&mut out, b"IEND", &[]);
    out
}

#[test]
fn bad_maps_are_refused_with_the_file_and_key() {
    let dir = std::env::temp_dir().join(format!("trample-maps-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    image::GrayImage::new(1, 1)
        .save(dir.join("tiny.png"))
        .unwrap();
    std::fs::write(dir.join("text.png"), "not a png").unwrap();
    std::fs::write(dir.join("huge.png"), huge_png_header(60_000, 60_000)).unwrap();
    let outcome = |maps: &str| {
        let text =
            format!("[field]\npatches = [1, 1]\ncells_per_patch = 8\n[field.maps]\n{maps}\n");
        std::fs::write(dir.join("scene.toml"), text).unwrap();
        match Scene::load(&dir.join("scene.toml")).and_then(|s| s.build()) {
            Ok(_) => "accepted".to_string(),
            Err(e) => e.to_string().replace(&dir.display().to_string(), "<dir>"),
        }
    };
    let cases = [
        (
            r#"density = "missing.png""#,
            "<dir>/scene.toml: field.maps.density = <dir>/missing.png: No such file or directory (os error 2)",
        ),
        (
            r#"height = "../x.png""#,
            "<dir>/scene.toml: field.maps.height = \"../x.png\": climbs above <dir> with `..`; it must stay inside that folder",
        ),
        (
            r#"tint = "tiny.png""#,
            "<dir>/scene.toml: field.maps.tint = <dir>/tiny.png: 1x1 pixels; at least 2x2 are needed",
        ),
        (
            r#"density = "text.png""#,
            "<dir>/scene.toml: field.maps.density = <dir>/text.png: Format error decoding Png: Invalid PNG signature.",
        ),
        (
            r#"height = "huge.png""#,
            "<dir>/scene.toml: field.maps.height = <dir>/huge.png: 60000x60000 pixels, too large to decode (Memory limit exceeded: the image decoder allows 512 MiB); allowed: a smaller image (a map is sampled once per cell: more pixels than the field has cells add nothing)",
        ),
        (
            r#"density = "sub""#,
            "<dir>/scene.toml: field.maps.density = <dir>/sub: not a regular file; allowed: a PNG image file",
        ),
        (
            "height_range = [1.0, 0.5]",
            "<dir>/scene.toml: field.maps.height_range = [1, 0.5]: each must be in [0, 10] and the first not above the second",
        ),
        (
            "height_range = [0.0, inf]",
            "<dir>/scene.toml: field.maps.height_range = [0, inf]: each must be in [0, 10] and the first not above the second",
        ),
        (
            "colour = \"x.png\"",
            "<dir>/scene.toml:5:1: unknown field `colour`, expected one of `density`, `height`, `height_range`, `tint` (in [field.maps])",
        ),
    ];
    for (maps, want) in cases {
        assert_eq!(outcome(maps), want, "{maps}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
