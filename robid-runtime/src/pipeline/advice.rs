//! Processing settings that give a result without an error but not the one meant: told
//! as quality warnings of the identification, with the setting that mends them.

use crate::data::{Config, Derivative, Record, Signal};
use crate::error::Result;
use crate::estimate::QualityWarning;

/// The warnings that `config`'s processing of `data` calls for:
/// [`QualityWarning::UnfilteredDerivatives`] when joint positions are differentiated by
/// central differences without a low-pass on them (a config without `[processing]
/// lowpass`: each differentiation multiplies the positions' noise by up to twice the
/// sample rate, and noise in the regressor biases least squares).
pub(crate) fn processing_warnings(
    config: &Config,
    data: &dyn Record,
) -> Result<Vec<QualityWarning>> {
    let p = &config.processing;
    let first = data.read(0, data.samples().min(1))?;
    let measured = |d: Derivative, has: bool| d != Derivative::Differentiate && has;
    let differentiated: Vec<&'static str> = [
        ("velocities", measured(p.velocity, first.qd.is_some())),
        (
            "accelerations",
            measured(p.acceleration, first.qdd.is_some()),
        ),
    ]
    .into_iter()
    .filter(|(_, m)| !m)
    .map(|(what, _)| what)
    .collect();
    let filtered = p
        .lowpass
        .as_ref()
        .is_some_and(|lp| lp.signals.contains(&Signal::Q));
    // a Savitzky-Golay window no wider than its polynomial interpolates: differences too
    let central = match p.differentiation.savitzky_golay() {
        Ok(None) => true,
        Ok(Some(sg)) => !sg.smooths(),
        Err(_) => false,
    };
    let mut warnings = Vec::new();
    if !differentiated.is_empty() && !filtered && central {
        warnings.push(QualityWarning::UnfilteredDerivatives {
            derived: differentiated.join(" and "),
        });
    }
    Ok(warnings)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::data::{Config, load};
    use crate::estimate::QualityWarning;
    use crate::pipeline::identify;
    use crate::pipeline::tests::synthetic::{CONFIG, DOF, Synthetic, csv_with_noise};

    /// Positions differentiated without a low-pass on them are warned of, naming what
    /// was differentiated and the setting that mends it; a low-pass on "q", a
    /// Savitzky-Golay differentiation, or measured velocities and accelerations, not.
    #[test]
    fn unfiltered_derivatives_are_warned_of() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("run.csv");
        std::fs::write(&file, csv_with_noise(6000, 1000.0, [1e-3; DOF])).unwrap();
        let lowpass = "lowpass = { cutoff = 20.0, order = 4, signals = [\"q\"] }\n";
        let warned = |config: &str| {
            let config = Config::from_toml_str(config, Path::new("synthetic.toml")).unwrap();
            let data = load(&config, std::slice::from_ref(&file), DOF).unwrap();
            let id = identify(&Synthetic::default(), &data, &config).unwrap();
            id.estimate.warnings.into_iter().find_map(|w| match w {
                QualityWarning::UnfilteredDerivatives { derived } => Some(derived),
                _ => None,
            })
        };
        assert_eq!(warned(CONFIG), None);
        let unfiltered = CONFIG.replace(lowpass, "");
        assert_ne!(unfiltered, CONFIG);
        assert_eq!(
            warned(&unfiltered).as_deref(),
            Some("velocities and accelerations")
        );
        let torque_only = CONFIG.replace("signals = [\"q\"]", "signals = [\"tau\"]");
        assert!(warned(&torque_only).is_some());
        let smoothed = unfiltered.replace(
            "[processing]\n",
            "[processing]\ndifferentiation = { method = \"savitzky-golay\", window = 31, order = 3 }\n",
        );
        assert_eq!(warned(&smoothed), None);
        // a window of order + 1 samples interpolates them: central differences again
        let interpolated = unfiltered.replace(
            "[processing]\n",
            "[processing]\ndifferentiation = { method = \"savitzky-golay\", window = 3, order = 2 }\n",
        );
        assert_eq!(
            warned(&interpolated).as_deref(),
            Some("velocities and accelerations")
        );
        let message = QualityWarning::UnfilteredDerivatives {
            derived: "velocities".into(),
        }
        .to_string();
        assert!(
            message.contains("lowpass = { cutoff = \"auto\", signals = [\"q\"] }"),
            "{message}"
        );
    }
}
