//! Reports (docs/identification.md#reports): JSON for machines, a text table for people,
//! SVG plots of measured vs predicted torque and residual per joint, and one
//! self-contained HTML page with all of it.

mod html;
mod json;
mod plot;
mod runs;
mod segments;
mod table;
mod unit;

pub use html::{html_report, write_html};
pub use json::{FitEntry, ParameterEntry, ReferenceFit, Report, ReportWarning, ValidationEntry};
pub use plot::{plot_torques, torque_svg};
pub use runs::{RunEntry, RunParameterEntry, RunsEntry};
pub use segments::SegmentsEntry;
pub use table::{fixed, text_table};
pub use unit::{PRISMATIC, REVOLUTE, joint_units, torque_unit};
