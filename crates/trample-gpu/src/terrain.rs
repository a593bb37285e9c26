//! The terrain on the GPU, for the ground guard of the deformation stages
//! (DESIGN §2, §6): `trample::field::Terrain` as one table of `f32` that
//! `guard.wgsl` reads (its header comment has the layout). Flat ground is
//! its height; a height map its samples; value noise the lattice values of
//! both octaves over the field and a blade's reach beyond it, computed by
//! the core's own `terrain::lattice`, so the GPU interpolates the same
//! values the CPU does.

use trample::field::terrain::{HeightGrid, SECOND_OCTAVE_SEED, lattice};
use trample::field::{FieldLayout, Terrain};

use crate::error::GpuError;

/// Entries before a height map's samples.
const HEADER: usize = 16;

/// `guard.wgsl`'s table for `terrain` under a field of `layout` whose
/// blades reach at most `reach` metres from their roots.
///
/// # Errors
/// [`GpuError::TooLarge`] when the table would pass `limit` bytes (a noise
/// wavelength far below the field's size), or lattice coordinates beyond
/// what an `f32` holds exactly.
pub fn table(
    terrain: &Terrain,
    layout: &FieldLayout,
    reach: f32,
    limit: u64,
) -> Result<Vec<f32>, GpuError> {
    let mut t = vec![0.0f32; HEADER];
    match terrain {
        Terrain::Flat(h) => {
            t[0] = 0.0;
            t[1] = *h;
        }
        Terrain::Heightmap(HeightGrid {
            dims,
            heights,
            origin,
            size,
        }) => {
            let bytes = (HEADER + heights.len()) as u64 * 4;
            if bytes > limit || dims.iter().any(|&d| d >= 1 << 24) {
                return Err(GpuError::TooLarge {
                    what: "the terrain's height map",
                    bytes,
                    limit,
                });
            }
            t[..7].copy_from_slice(&[
                2.0,
                dims[0] as f32,
                dims[1] as f32,
                origin[0],
                origin[1],
                size[0],
                size[1],
            ]);
            t.extend_from_slice(heights);
        }
        Terrain::Noise {
            amplitude,
            wavelength,
            seed,
        } => {
            t[0] = 1.0;
            t[1] = *amplitude;
            t[2] = *wavelength;
            let [gx, gz] = layout.grid_size();
            let lo = [layout.origin[0] - reach, layout.origin[1] - reach];
            let hi = [
                layout.origin[0] + gx as f32 * layout.cell_size + reach,
                layout.origin[1] + gz as f32 * layout.cell_size + reach,
            ];
            for (k, (scale, seed)) in [
                (1.0 / wavelength, *seed),
                (2.0 / wavelength, seed ^ SECOND_OCTAVE_SEED),
            ]
            .into_iter()
            .enumerate()
            {
                // Lattice points around every coordinate the CPU floors,
                // one spare each side for rounding.
                let i0 = (lo[0] * scale).floor() as i64 - 1;
                let j0 = (lo[1] * scale).floor() as i64 - 1;
                let i1 = (hi[0] * scale).floor() as i64 + 2;
                let j1 = (hi[1] * scale).floor() as i64 + 2;
                let (nx, nz) = ((i1 - i0 + 1) as u64, (j1 - j0 + 1) as u64);
                let bytes = (t.len() as u64 + nx * nz) * 4;
                let exact = [i0, j0, i1, j1].iter().all(|v| v.abs() < 1 << 23);
                if bytes > limit || !exact {
                    return Err(GpuError::TooLarge {
                        what: "the terrain's noise lattice (a wavelength far below the field's size)",
                        bytes,
                        limit,
                    });
                }
                let (base, first) = (3 + 5 * k, t.len() as f32);
                t[base..base + 5]
                    .copy_from_slice(&[i0 as f32, j0 as f32, nx as f32, nz as f32, first]);
                for j in j0..=j1 {
                    t.extend((i0..=i1).map(|i| lattice(i, j, seed)));
                }
            }
        }
    }
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout() -> FieldLayout {
        let text = "name = \"t\"\n[field]\npatches = [2, 2]\ncells_per_patch = 4\n";
        trample::scene::Scene::parse(text, "t.toml", std::path::Path::new("."))
            .and_then(|s| s.build())
            .expect("scene builds")
            .field
            .layout
    }

    #[test]
    fn noise_table_holds_the_lattice_around_the_field() {
        let terrain = Terrain::Noise {
            amplitude: 0.5,
            wavelength: 0.7,
            seed: 9,
        };
        let l = layout();
        let t = table(&terrain, &l, 0.3, u64::MAX).unwrap();
        assert_eq!(t[0], 1.0);
        for k in 0..2 {
            let base = 3 + 5 * k;
            let (i0, j0, nx, nz, first) = (
                t[base] as i64,
                t[base + 1] as i64,
                t[base + 2] as i64,
                t[base + 3] as i64,
                t[base + 4] as usize,
            );
            let seed = if k == 0 { 9 } else { 9 ^ SECOND_OCTAVE_SEED };
            // A corner beyond the field by the reach is inside the table.
            let scale = (k + 1) as f32 / 0.7;
            let x = (l.origin[0] - 0.3) * scale;
            assert!(x.floor() as i64 >= i0, "octave {k}");
            assert_eq!(
                t[first + (nz as usize - 1) * nx as usize],
                lattice(i0, j0 + nz - 1, seed)
            );
        }
    }

    #[test]
    fn absurd_noise_is_refused_by_name() {
        let terrain = Terrain::Noise {
            amplitude: 0.5,
            wavelength: 1e-5,
            seed: 0,
        };
        let e = table(&terrain, &layout(), 0.3, 1 << 27).unwrap_err();
        assert!(e.to_string().contains("noise lattice"), "{e}");
    }
}
