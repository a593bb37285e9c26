//! [`recover_blade`](crate::recovery::recover_blade) on four blades at once
//! (ours, issue 16): the same bits, blade by blade.
//!
//! A recovering blade's cost is its length preservation (Fig. 7): a chain
//! of square roots and divisions, each segment waiting for the one below,
//! so one blade keeps the arithmetic units waiting. Four blades side by
//! side (structure of arrays, one lane a blade) run four chains in the time
//! of about one. Every lane computes what the scalar code computes, in the
//! same order, with the same IEEE operations — `(x·x + y·y) + z·z` as
//! glam's `length_squared`, the division of each component by the square
//! root, `from + dir · len` — so the results are the scalar ones bit for
//! bit. A lane that leaves the common path (a segment of zero length, an end
//! the ground guard must lift, an invalid blade) is finished by the scalar
//! code from where `recovery_start` left it, as are lanes of different
//! lengths.

use glam::Vec3A;

use crate::deform::bend::valid_blade;
use crate::field::{MAX_SEGMENTS, Terrain};
use crate::recovery::{REST_EPSILON, RecoveryParams, Start, recovery_finish, recovery_start};

/// Blades a group holds.
pub const LANES: usize = 4;

/// One blade of a group given to [`recover_blades_wide`].
pub struct Lane<'a> {
    /// Its vertices, root first, `n + 1` (updated in place).
    pub verts: &'a mut [Vec3A],
    /// Its rest vertices, `n + 1`.
    pub rest: &'a [Vec3A],
    /// The rest length of every segment, metres.
    pub seg_len: f32,
    /// Its recovery time this step, seconds.
    pub dt: f32,
    /// Its track owner's settings.
    pub params: &'a RecoveryParams,
}

/// [`recover_blade`](crate::recovery::recover_blade) on each of four blades,
/// the same bits: returns, per lane, whether the blade is now at rest.
pub fn recover_blades_wide(
    mut lanes: [Lane<'_>; LANES],
    terrain: &Terrain,
    clearance: f32,
) -> [bool; LANES] {
    let mut done = [false; LANES];
    // Per lane: the fraction to blend by, for the lanes that run wide.
    let mut q = [None::<f32>; LANES];
    let n = lanes[0].verts.len().saturating_sub(1);
    for (l, lane) in lanes.iter_mut().enumerate() {
        match recovery_start(lane.verts, lane.rest, lane.dt, lane.params) {
            Start::Done(at_rest) => done[l] = at_rest,
            Start::Blend(f) => {
                let common = lane.verts.len() == n + 1
                    && (1..=MAX_SEGMENTS).contains(&n)
                    && valid_blade(lane.verts, lane.seg_len);
                if common {
                    q[l] = Some(f);
                } else {
                    done[l] =
                        recovery_finish(lane.verts, lane.rest, lane.seg_len, f, terrain, clearance);
                }
            }
        }
    }
    // The lanes that do not run wide compute a copy of the first one that
    // does (their results are not kept).
    let Some(model) = q.iter().position(Option::is_some) else {
        return done;
    };
    let clearance = if clearance.is_finite() {
        clearance
    } else {
        0.0
    };
    let src = |l: usize| if q[l].is_some() { l } else { model };
    let mut v = [[[0.0f32; LANES]; 3]; MAX_SEGMENTS + 1];
    let mut r = [[[0.0f32; LANES]; 3]; MAX_SEGMENTS + 1];
    let mut f = [0.0f32; LANES];
    let mut len = [0.0f32; LANES];
    for l in 0..LANES {
        let s = &lanes[src(l)];
        for k in 0..=n {
            for c in 0..3 {
                v[k][c][l] = s.verts[k][c];
                r[k][c][l] = s.rest[k][c];
            }
        }
        f[l] = q[src(l)].unwrap_or(0.0);
        len[l] = s.seg_len;
    }
    // Blend (`v += (r − v) · q`).
    for k in 1..=n {
        for c in 0..3 {
            for l in 0..LANES {
                v[k][c][l] += (r[k][c][l] - v[k][c][l]) * f[l];
            }
        }
    }
    // Length preservation from the root (`bend::preserve_from`, first = 1),
    // on its common path: a segment's own direction, its end kept above
    // the ground guard.
    let mut common = [true; LANES];
    for i in 1..=n {
        let mut d = [[0.0f32; LANES]; 3];
        let mut len2 = [0.0f32; LANES];
        for l in 0..LANES {
            for c in 0..3 {
                d[c][l] = v[i][c][l] - v[i - 1][c][l];
            }
            len2[l] = (d[0][l] * d[0][l] + d[1][l] * d[1][l]) + d[2][l] * d[2][l];
        }
        for l in 0..LANES {
            let root = len2[l].sqrt();
            for c in 0..3 {
                v[i][c][l] = v[i - 1][c][l] + (d[c][l] / root) * len[l];
            }
        }
        for l in 0..LANES {
            let clears = v[i][1][l] >= terrain.height_at(v[i][0][l], v[i][2][l]) + clearance;
            common[l] &= len2[l].is_finite() && len2[l] > 1e-24 && clears;
        }
    }
    for (l, lane) in lanes.iter_mut().enumerate() {
        let Some(f) = q[l] else {
            continue;
        };
        if !common[l] {
            done[l] = recovery_finish(lane.verts, lane.rest, lane.seg_len, f, terrain, clearance);
            continue;
        }
        let mut at_rest = true;
        for k in 0..=n {
            let d = [0, 1, 2].map(|c| v[k][c][l] - r[k][c][l]);
            at_rest &= (d[0] * d[0] + d[1] * d[1]) + d[2] * d[2] < REST_EPSILON * REST_EPSILON;
        }
        if at_rest {
            lane.verts.copy_from_slice(lane.rest);
        } else {
            for (k, out) in lane.verts.iter_mut().enumerate() {
                *out = Vec3A::new(v[k][0][l], v[k][1][l], v[k][2][l]);
            }
        }
        done[l] = at_rest;
    }
    done
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recovery::recover_blade;
    use crate::test_rng::XorShift;

    /// A blade of `n` segments of 0.1 m rooted at `root`, bent by a random
    /// amount (some flattened onto the ground, some barely moved, some at
    /// rest, some with a zero-length segment or driven into the ground),
    /// and its rest shape.
    fn blade(rng: &mut XorShift, n: usize, root: Vec3A, case: u64) -> (Vec<Vec3A>, Vec<Vec3A>) {
        let lean = Vec3A::new(rng.range(-0.05, 0.05), 1.0, rng.range(-0.05, 0.05)).normalize();
        let rest: Vec<Vec3A> = (0..=n).map(|k| root + lean * (0.1 * k as f32)).collect();
        let mut v = rest.clone();
        let push = Vec3A::new(
            rng.range(-1.0, 1.0),
            rng.range(-0.3, 0.0),
            rng.range(-1.0, 1.0),
        );
        let amount = match case % 6 {
            0 => 0.0,
            1 => 1e-3,
            2 => 0.02,
            _ => rng.range(0.05, 1.0),
        };
        for (k, p) in v.iter_mut().enumerate().skip(1) {
            *p += push * (amount * k as f32 / n as f32);
        }
        if case % 11 == 3 && n >= 2 {
            v[2] = v[1];
        }
        if case % 13 == 5 {
            v[n].y = root.y - 0.05;
        }
        (v, rest)
    }

    /// Four blades at a time give [`recover_blade`]'s bits, blade by blade:
    /// random blades (flat and hilly ground, 1 to 8 segments, some at rest,
    /// barely moved, in the tail or flattened, some held, some with
    /// degenerate segments or vertices in the ground), every recovery
    /// time and setting; groups of like blades and groups that mix
    /// segment counts. Fails if a lane's arithmetic differs in one ulp.
    #[test]
    fn four_blades_at_once_give_the_scalar_bits() {
        let mut rng = XorShift(0x0ddb_a11c_afe0_0035);
        let hills = Terrain::Noise {
            amplitude: 0.3,
            wavelength: 2.0,
            seed: 7,
        };
        let settings = [
            RecoveryParams {
                recovery_s: 2.0,
                trail: 0.0,
            },
            RecoveryParams {
                recovery_s: 6.0,
                trail: 2.0,
            },
            RecoveryParams {
                recovery_s: f32::INFINITY,
                trail: 0.0,
            },
            RecoveryParams {
                recovery_s: 0.0,
                trail: 0.0,
            },
        ];
        let (mut wide, mut at_rest) = (0, 0);
        for group in 0..6000u64 {
            let terrain = if group % 3 == 0 {
                hills.clone()
            } else {
                Terrain::Flat(0.0)
            };
            let n0 = 1 + (group % 8) as usize;
            let mut blades = Vec::new();
            for l in 0..LANES as u64 {
                // Every fifth group mixes segment counts.
                let n = if group % 5 == 4 {
                    1 + ((group + l) % 8) as usize
                } else {
                    n0
                };
                let root = Vec3A::new(rng.range(-3.0, 3.0), 0.0, rng.range(-3.0, 3.0));
                let root = root + Vec3A::Y * terrain.height_at(root.x, root.z);
                let (v, rest) = blade(&mut rng, n, root, group * 4 + l);
                let dt = [1.0 / 60.0, 0.0, 0.25, 1.0 / 144.0][(rng.next_u64() % 4) as usize];
                let p = settings[(rng.next_u64() % 8).min(3) as usize];
                blades.push((v, rest, dt, p));
            }
            let mut want = blades.clone();
            let want_done: Vec<bool> = want
                .iter_mut()
                .map(|(v, rest, dt, p)| recover_blade(v, rest, 0.1, *dt, p, &terrain, 0.002))
                .collect();
            let mut got = blades.clone();
            let [a, b, c, d] = &mut got[..] else {
                unreachable!()
            };
            let lanes = [a, b, c, d].map(|(v, rest, dt, p)| Lane {
                verts: v,
                rest,
                seg_len: 0.1,
                dt: *dt,
                params: p,
            });
            let got_done = recover_blades_wide(lanes, &terrain, 0.002);
            assert_eq!(got_done.to_vec(), want_done, "group {group}");
            for ((g, w), before) in got.iter().zip(&want).zip(&blades) {
                let bits = |v: &[Vec3A]| -> Vec<[u32; 3]> {
                    v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
                };
                assert_eq!(bits(&g.0), bits(&w.0), "group {group}: {:?}", blades);
                wide += usize::from(g.0 != before.0);
            }
            at_rest += want_done.iter().filter(|&&d| d).count();
        }
        assert!(wide > 5000 && at_rest > 1000, "{wide} {at_rest}");
    }
}
