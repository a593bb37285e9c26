//! A compute kernel: one WGSL module (with `blade.wgsl` prepended where the
//! stage shares it), one explicit bind-group layout shared by all its entry
//! points, one pipeline per entry point. Compiled once, kept apart from the
//! buffers it runs on.

/// How a binding is used.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Slot {
    Uniform,
    Read,
    ReadWrite,
}

/// Pipelines of one module over one bind-group layout.
pub(crate) struct Kernel {
    layout: wgpu::BindGroupLayout,
    pipelines: Vec<wgpu::ComputePipeline>,
    /// The last bind groups made, by their buffers ([`Kernel::bind`]).
    groups: BindCache,
}

/// Bind groups kept for reuse, by the buffers they bind (binding `i` =
/// the `i`-th buffer): a stage binds the same buffers step after step, and
/// making a bind group is validation and bookkeeping the host would pay
/// again every step. The least recently bound group is pushed out past the
/// cache's size, and with it the hold on its buffers (a table made again
/// leaves its old groups unbound: they go first). The size starts at the
/// caller's `keep` and doubles (up to [`MOST_KEPT_GROUPS`]) whenever a set
/// pushed out is asked for again: a step that binds more sets than the
/// cache holds (a field of many chunks) would otherwise make every group
/// again every step.
#[derive(Default)]
pub(crate) struct BindCache {
    kept: std::sync::Mutex<Kept>,
}

/// [`BindCache`]'s contents.
#[derive(Default)]
struct Kept {
    /// The groups and their buffers, least recently bound first.
    groups: Vec<(Vec<wgpu::Buffer>, wgpu::BindGroup)>,
    /// Fingerprints of the sets pushed out (most recent last, at most
    /// [`MOST_KEPT_GROUPS`]); the buffers themselves are not held.
    pushed_out: Vec<u64>,
    /// The size grown to (0: the caller's `keep`).
    grown: usize,
}

/// The most bind groups one cache keeps, however often it is asked again
/// for sets it pushed out.
pub(crate) const MOST_KEPT_GROUPS: usize = 256;

/// Bind groups made by every cache of this process since it started
/// ([`bind_groups_made`]).
static GROUPS_MADE: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// How many bind groups the kernels' caches have made in this process: a
/// diagnostic (a steady step should make none; `tests/bind_groups.rs`).
#[must_use]
pub fn bind_groups_made() -> u64 {
    GROUPS_MADE.load(std::sync::atomic::Ordering::Relaxed)
}

/// A fingerprint of a set of buffers (by identity, as `==` compares them).
fn fingerprint(buffers: &[&wgpu::Buffer]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    buffers.len().hash(&mut h);
    for b in buffers {
        b.hash(&mut h);
    }
    h.finish()
}

impl BindCache {
    /// The group of `buffers` for `layout`: the one made before if still
    /// kept, else a new one, kept (the cache holds at least `keep`, the
    /// least recently bound pushed out). One cache serves one layout.
    pub(crate) fn bind(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        buffers: &[&wgpu::Buffer],
        keep: usize,
    ) -> wgpu::BindGroup {
        let mut kept = self
            .kept
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let same = |b: &[wgpu::Buffer]| {
            b.len() == buffers.len() && b.iter().zip(buffers).all(|(a, b)| a == *b)
        };
        if let Some(at) = kept.groups.iter().position(|(b, _)| same(b)) {
            let entry = kept.groups.remove(at);
            let group = entry.1.clone();
            kept.groups.push(entry);
            return group;
        }
        let print = fingerprint(buffers);
        if let Some(at) = kept.pushed_out.iter().position(|&f| f == print) {
            // Asked again for a set it let go: too small for a step.
            kept.pushed_out.remove(at);
            kept.grown = kept.grown.max(keep).max(1).saturating_mul(2);
        }
        let size = kept.grown.max(keep).clamp(1, MOST_KEPT_GROUPS);
        let group = make_group(device, layout, buffers);
        GROUPS_MADE.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        while kept.groups.len() >= size {
            let (old, _) = kept.groups.remove(0);
            let old: Vec<&wgpu::Buffer> = old.iter().collect();
            if kept.pushed_out.len() >= MOST_KEPT_GROUPS {
                kept.pushed_out.remove(0);
            }
            kept.pushed_out.push(fingerprint(&old));
        }
        kept.groups
            .push((buffers.iter().map(|&b| b.clone()).collect(), group.clone()));
        group
    }
}

/// A new bind group of `buffers` (binding `i` = `buffers[i]`) for `layout`.
fn make_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    buffers: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = buffers
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout,
        entries: &entries,
    })
}

/// Bind groups a kernel keeps for reuse at first ([`BindCache`]; a few per
/// chunk; more once a step binds more).
const KEPT_GROUPS: usize = 8;

impl Kernel {
    /// Compiles `entries` of `source`; binding `i` of group 0 is `slots[i]`.
    pub(crate) fn new(
        device: &wgpu::Device,
        label: &str,
        source: &str,
        slots: &[Slot],
        entries: &[&str],
    ) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let layout_entries: Vec<wgpu::BindGroupLayoutEntry> = slots
            .iter()
            .enumerate()
            .map(|(i, s)| wgpu::BindGroupLayoutEntry {
                binding: i as u32,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: match s {
                        Slot::Uniform => wgpu::BufferBindingType::Uniform,
                        Slot::Read => wgpu::BufferBindingType::Storage { read_only: true },
                        Slot::ReadWrite => wgpu::BufferBindingType::Storage { read_only: false },
                    },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &layout_entries,
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipelines = entries
            .iter()
            .map(|e| compute_pipeline(device, &pipeline_layout, &module, e))
            .collect();
        Self {
            layout,
            pipelines,
            groups: BindCache::default(),
        }
    }

    /// A bind group of `buffers`, binding `i` = `buffers[i]`: the one made
    /// for these buffers before, if the kernel still keeps it (the host
    /// records a step without making the same groups again).
    pub(crate) fn bind(&self, device: &wgpu::Device, buffers: &[&wgpu::Buffer]) -> wgpu::BindGroup {
        self.groups.bind(device, &self.layout, buffers, KEPT_GROUPS)
    }

    /// A new bind group of `buffers`, not kept: for a buffer made for one
    /// dispatch, which [`Kernel::bind`] would keep alive for nothing.
    pub(crate) fn make_group(
        &self,
        device: &wgpu::Device,
        buffers: &[&wgpu::Buffer],
    ) -> wgpu::BindGroup {
        make_group(device, &self.layout, buffers)
    }

    /// Records entry point `entry` (index into the `entries` given to
    /// [`Kernel::new`]) over `groups` workgroups, in a pass of its own.
    pub(crate) fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        entry: usize,
        group: &wgpu::BindGroup,
        groups: (u32, u32),
    ) {
        self.dispatch_in(&mut begin_pass(encoder), entry, group, groups);
    }

    /// As [`Kernel::dispatch`], into `pass` (one pass for a run of
    /// dispatches: a compute pass synchronises each dispatch with the ones
    /// before it as separate passes do — in WebGPU each dispatch is a usage
    /// scope of its own — and costs the host one pass to record).
    pub(crate) fn dispatch_in(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        entry: usize,
        group: &wgpu::BindGroup,
        groups: (u32, u32),
    ) {
        pass.set_pipeline(&self.pipelines[entry]);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
    }
}

/// The pipeline of entry point `entry` of `module` over `layout`, labelled
/// with the entry's name.
pub(crate) fn compute_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
) -> wgpu::ComputePipeline {
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: Some(layout),
        module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions::default(),
        cache: None,
    })
}

/// A 12-byte buffer for one indirect dispatch's workgroup counts (written
/// by a one-thread pass: `STORAGE | INDIRECT`), or one bound in its place
/// while the dispatch reads them (`STORAGE`: a buffer is not both an
/// indirect source and writable storage in one dispatch).
pub(crate) fn args_buffer(
    device: &wgpu::Device,
    label: &str,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: 12,
        usage,
        mapped_at_creation: false,
    })
}

/// A compute pass for [`Kernel::dispatch_in`] and
/// [`Kernel::dispatch_indirect_in`].
pub(crate) fn begin_pass(encoder: &mut wgpu::CommandEncoder) -> wgpu::ComputePass<'_> {
    encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: None,
        timestamp_writes: None,
    })
}

impl Kernel {
    /// As [`Kernel::dispatch_in`], with the workgroup counts read from
    /// `args` (three `u32`, written by an earlier dispatch).
    pub(crate) fn dispatch_indirect_in(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        entry: usize,
        group: &wgpu::BindGroup,
        args: &wgpu::Buffer,
    ) {
        self.dispatch_indirect_at(pass, entry, group, args, 0);
    }

    /// As [`Kernel::dispatch_indirect_in`], with the arguments at byte
    /// `offset` of `args`.
    pub(crate) fn dispatch_indirect_at(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        entry: usize,
        group: &wgpu::BindGroup,
        args: &wgpu::Buffer,
        offset: u64,
    ) {
        pass.set_pipeline(&self.pipelines[entry]);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups_indirect(args, offset);
    }
}

/// Workgroups (x, y) covering `count` threads of 64: at most
/// `max_per_dimension` in x (the shaders index x + y · x_groups · 64).
pub(crate) fn grid(count: u32, max_per_dimension: u32) -> (u32, u32) {
    let groups = count.div_ceil(64).max(1);
    let max = max_per_dimension.max(1);
    (groups.min(max), groups.div_ceil(max))
}

/// Blades a thread takes in `bend`, the pass over the whole field that does
/// nothing for most blades (`RUN` in `blade.wgsl`, which says why).
pub(crate) const RUN: u32 = 8;

/// The workgroups of such a pass, from the grid of one blade a thread: as
/// many rows, `RUN` times fewer columns (rounded up). `run_start` in
/// `blade.wgsl` numbers the threads of this grid.
pub(crate) fn run_grid(groups: (u32, u32)) -> (u32, u32) {
    (groups.0.div_ceil(RUN), groups.1)
}

#[cfg(test)]
mod tests {
    use super::{RUN, grid, run_grid};

    /// `run_start` in `blade.wgsl`, on the host.
    fn run_start(gid: (u32, u32), groups_x: u32) -> u32 {
        let gx = groups_x.div_ceil(RUN);
        (gid.0 + gid.1 * gx * 64) * RUN
    }

    #[test]
    fn a_run_grid_takes_every_blade_once() {
        for (count, max) in [
            (1, 65_535),
            (63, 65_535),
            (200, 2),
            (262_144, 65_535),
            (1_000_003, 1_000),
            (16_777_216, 65_535),
            (5_000, 3),
        ] {
            let (gx, gy) = run_grid(grid(count, max));
            let mut seen = vec![0u8; count as usize];
            for y in 0..gy {
                for x in 0..gx * 64 {
                    let first = run_start((x, y), grid(count, max).0);
                    for b in first..(first + RUN).min(count) {
                        seen[b as usize] += 1;
                    }
                }
            }
            assert!(
                seen.iter().all(|&n| n == 1),
                "{count} blades, {max} groups at most: {} blades not taken once",
                seen.iter().filter(|&&n| n != 1).count()
            );
        }
    }
}
