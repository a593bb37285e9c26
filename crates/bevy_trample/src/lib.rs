#![doc = include_str!("../README.md")]
//!
//! # Layout
//! - [`field`]: [`TrampleField`], the meadow (the simulation) as a resource.
//! - [`trampler`]: the [`Trampler`] component and the system that keeps the
//!   simulation's bodies in step with the entities.
//! - [`step`]: the fixed-timestep step and [`TrampleCamera`].
//! - [`host`]: the one place the plugin calls the core's host API.
//! - [`mesh`]: Bevy meshes as the core's triangle meshes.
//! - [`skin`]: skinned meshes posed on the CPU for the collision.
//! - `gpu_path` (feature `gpu`): the field stepped on trample's GPU path
//!   with Bevy's device.
//! - [`diagnostics`]: per-stage timings as Bevy diagnostics.
//! - `render` (feature `render`): drawing with Bevy's renderer.

pub mod diagnostics;
pub mod error;
pub mod field;
#[cfg(feature = "gpu")]
pub mod gpu_path;
pub mod host;
pub mod mesh;
#[cfg(feature = "render")]
pub mod render;
pub mod skin;
pub mod step;
pub mod trampler;

pub use error::TrampleError;
pub use field::{TrampleBackend, TrampleField};
#[cfg(feature = "render")]
pub use render::look::GrassLook;
pub use step::{TrampleCamera, TramplerSkinRefused};
pub use trampler::{Trampler, TramplerBody, TramplerError, TramplerPoseRefused, TramplerShape};

use bevy::prelude::*;
use bevy::transform::TransformSystems;

/// The plugin: simulates the [`TrampleField`] resource with every
/// [`Trampler`] entity in it, and (feature `render`, when the app renders)
/// draws it with Bevy's renderer.
///
/// Add it after Bevy's own plugins (`DefaultPlugins`, or `MinimalPlugins`
/// plus `AssetPlugin` and `TransformPlugin` and the `Mesh` asset for a
/// headless app).
#[derive(Clone, Debug, Default)]
pub struct TramplePlugin;

/// The plugin's systems, to order a game's own against.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TrampleSystems {
    /// `PostUpdate`, after transform propagation: tramplers added, changed
    /// or removed become, change or lose their bodies.
    SyncBodies,
    /// `FixedUpdate`: one simulation step of the fixed timestep. Move
    /// tramplers in `FixedUpdate` before it for contact speeds that follow
    /// the motion step by step.
    Step,
}

impl Plugin for TramplePlugin {
    fn build(&self, app: &mut App) {
        app.configure_sets(
            PostUpdate,
            TrampleSystems::SyncBodies.after(TransformSystems::Propagate),
        )
        .add_systems(
            PostUpdate,
            trampler::sync_bodies.in_set(TrampleSystems::SyncBodies),
        )
        .add_systems(FixedUpdate, step::step_field.in_set(TrampleSystems::Step));
        #[cfg(feature = "gpu")]
        app.add_systems(
            PostUpdate,
            step::refresh_gpu_lists.after(TrampleSystems::SyncBodies),
        );
        diagnostics::register(app);
        #[cfg(feature = "render")]
        if app.get_sub_app(bevy::render::RenderApp).is_some() {
            app.add_plugins(render::TrampleRenderPlugin);
        }
    }
}
