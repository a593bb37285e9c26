//! Per-stage timings of the simulation step as Bevy diagnostics
//! ([`bevy::diagnostic::DiagnosticsStore`]), so that a game's diagnostic
//! overlay or log shows them: `trample/step_ms`, one `trample/STAGE_ms` per
//! stage of the core's step (`StepTimings::stages`, DESIGN §7 order), and
//! counts of what the step did.

use bevy::diagnostic::{Diagnostic, DiagnosticPath, Diagnostics, RegisterDiagnostic};
use bevy::prelude::*;
use trample::StepTimings;

/// Wall-clock milliseconds of the whole step.
pub const STEP_MS: DiagnosticPath = DiagnosticPath::const_new("trample/step_ms");
/// Blades hit directly (DBG) in the last step.
pub const DBG_BLADES: DiagnosticPath = DiagnosticPath::const_new("trample/dbg_blades");
/// Blades reached by propagation only (PBG) in the last step.
pub const PBG_BLADES: DiagnosticPath = DiagnosticPath::const_new("trample/pbg_blades");
/// Blades away from rest (being recovered).
pub const DISPLACED_BLADES: DiagnosticPath = DiagnosticPath::const_new("trample/displaced_blades");

/// One path per stage of [`StepTimings::stages`], in that order.
pub const STAGE_MS: [DiagnosticPath; 10] = [
    DiagnosticPath::const_new("trample/poses_ms"),
    DiagnosticPath::const_new("trample/lod_ms"),
    DiagnosticPath::const_new("trample/broad_ms"),
    DiagnosticPath::const_new("trample/narrow_ms"),
    DiagnosticPath::const_new("trample/forces_ms"),
    DiagnosticPath::const_new("trample/propagation_ms"),
    DiagnosticPath::const_new("trample/deformation_ms"),
    DiagnosticPath::const_new("trample/contact_ms"),
    DiagnosticPath::const_new("trample/transitions_ms"),
    DiagnosticPath::const_new("trample/recovery_ms"),
];

/// Registers every path above.
pub(crate) fn register(app: &mut App) {
    for path in [STEP_MS, DBG_BLADES, PBG_BLADES, DISPLACED_BLADES]
        .into_iter()
        .chain(STAGE_MS)
    {
        let suffix = if path.as_str().ends_with("_ms") {
            "ms"
        } else {
            ""
        };
        app.register_diagnostic(Diagnostic::new(path).with_suffix(suffix));
    }
}

/// Records one step's timings and counts.
pub(crate) fn record(diagnostics: &mut Diagnostics, t: &StepTimings) {
    diagnostics.add_measurement(&STEP_MS, || t.total_ms);
    for (path, (_, ms)) in STAGE_MS.iter().zip(t.stages()) {
        diagnostics.add_measurement(path, || ms);
    }
    diagnostics.add_measurement(&DBG_BLADES, || f64::from(t.dbg_blades));
    diagnostics.add_measurement(&PBG_BLADES, || f64::from(t.pbg_blades));
    diagnostics.add_measurement(&DISPLACED_BLADES, || f64::from(t.displaced_blades));
}
