//! Per-axis identification (Milella; issue 17, item 8) of a simulated UR5e with noise that
//! differs between joints, the truth known:
//!
//! - every base parameter is determined by some joint's equation alone, and only by joints
//!   at or below its link (row j of the regressor holds links >= j);
//! - the reported deviations are honest: the truth lies within three of them;
//! - through the pipeline (`method = "per-axis"`) the estimate is the library's.

use robid_runtime::Model;
use robid_runtime::data::{Config, Derivative, Method};
use robid_runtime::estimate::per_axis;
use robid_runtime::model::BaseName;
use robid_runtime::pipeline::{identify, observation};
use robid_runtime::simulate::{Noise, Simulation};
use robid_symbolic::Drive;
use robots::Ur5e;
use tests::reference::by_name;

#[test]
fn milella_per_axis_identifies_a_simulated_ur5e() {
    let model = Ur5e;
    let r = by_name("ur5e");
    let standard = r.parameter_values(&r.robot().with_drive(Drive::NONE));
    let mut truth = vec![0.0; model.base_parameter_count()];
    model
        .base_from_standard_into(&standard, &mut truth)
        .unwrap();
    let noise = Noise {
        torque: vec![0.8, 0.8, 0.4, 0.1, 0.1, 0.05],
        position: 1e-5,
        ..Noise::default()
    };
    let data = Simulation {
        noise,
        seed: 21,
        ..Simulation::default()
    }
    .run(
        &model,
        &truth,
        &tests::reference::random_fourier("ur5e", 21, 30.0, 100.0),
    )
    .unwrap()
    .measured
    .dataset("ur5e-per-axis")
    .unwrap();
    let mut config = Config::default();
    config.processing.velocity = Derivative::Data;
    config.processing.acceleration = Derivative::Data;
    let (obs, _) = observation(&model, &data, &config).unwrap();
    let p = per_axis(&obs, 1e-10).unwrap();
    let e = &p.estimate;
    let inside = (0..truth.len())
        .filter(|&i| (e.values[i] - truth[i]).abs() <= 3.0 * e.std[i])
        .count();
    for a in &p.axes {
        println!(
            "axis {}: {} parameters, rank {}, cond {:.1}, {} determined, residual RMS {:.3}",
            a.joint,
            a.parameters,
            a.rank,
            a.condition_number,
            a.determined.len(),
            a.residual_rms
        );
    }
    println!(
        "per-axis: {inside} of {} within 3 std; sources {:?}",
        truth.len(),
        p.source
    );
    for (i, name) in e.names.iter().enumerate() {
        let link = name.parse::<BaseName>().map(|b| b.on.link + 1).unwrap();
        assert!(p.source[i] <= link, "{name} from joint {}", p.source[i]);
    }
    // 3-std intervals hold the truth with probability 0.997 each
    assert!(inside as f64 >= 0.95 * truth.len() as f64, "{inside}");
    config.estimation.method = Method::PerAxis;
    let id = identify(&model, &data, &config).unwrap();
    assert_eq!(id.estimate.values, e.values);
    assert_eq!(id.estimate.method.name(), "per-axis");
}
