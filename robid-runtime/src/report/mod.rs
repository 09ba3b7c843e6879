//! Reports (docs/identification.md#reports): JSON for machines, a text table for people,
//! SVG plots of measured vs predicted torque per joint.

mod json;
mod plot;
mod table;

pub use json::{FitEntry, ParameterEntry, Report, ReportWarning, ValidationEntry};
pub use plot::plot_torques;
pub use table::text_table;
