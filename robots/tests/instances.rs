//! `Model::run` of every reference robot through its AVX2 instances and through its plain
//! `f64` code (`robid_runtime::fused`): the two agree to rounding, and on a processor with
//! AVX2 and FMA they are two computations (some value differs in its last bits), so the
//! instances are really called. Without AVX2 both are the plain code, equal to the bit.
//! Either writes every entry of the output, the zeros too.
//!
//! A test binary of its own: `fused::set_enabled` is for the whole process, and no other
//! test may see it switch.

use robid_runtime::fused;
use robid_runtime::model::PROGRAMS;
use robid_runtime::rng::Rng;

#[test]
fn avx2_instances_agree_with_the_plain_code() {
    let avx2 = fused::dispatch();
    // taken wherever the processor has AVX2 and FMA and the build does not target them
    let expected = cfg!(target_arch = "x86_64")
        && !cfg!(all(target_feature = "avx2", target_feature = "fma"))
        && robid_runtime::trig::vector_available();
    assert_eq!(avx2, expected, "fused::dispatch()");
    let mut rng = Rng::from_state(7);
    for reference in &robots::REFERENCES {
        let model = reference.model();
        let sizes = model.sizes();
        let mut differ = 0;
        for program in &PROGRAMS {
            for _ in 0..5 {
                let inputs: Vec<Vec<f64>> = program
                    .inputs
                    .iter()
                    .map(|a| {
                        (0..a.size.len(sizes))
                            .map(|_| rng.uniform(-3.0, 3.0))
                            .collect()
                    })
                    .collect();
                let inputs: Vec<&[f64]> = inputs.iter().map(Vec::as_slice).collect();
                // NaN before: every entry must be written, zeros included (the outputs'
                // slices a caller passes hold what was there)
                let mut out = [
                    vec![f64::NAN; program.output.size.len(sizes)],
                    vec![f64::NAN; program.output.size.len(sizes)],
                ];
                for (enabled, out) in [true, false].into_iter().zip(&mut out) {
                    fused::set_enabled(enabled);
                    model.run(program.kind, &inputs, out).unwrap();
                }
                fused::set_enabled(true);
                let [instance, plain] = &out;
                let scale = plain.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
                for (i, (a, b)) in instance.iter().zip(plain).enumerate() {
                    let what = format!("{} {} [{i}]", reference.name, program.name);
                    assert!(a.is_finite() && b.is_finite(), "{what}: {a} vs {b}");
                    if avx2 {
                        assert!((a - b).abs() <= 1e-12 * scale, "{what}: {a} vs {b}");
                    } else {
                        assert_eq!(a.to_bits(), b.to_bits(), "{what}");
                    }
                    differ += usize::from(a.to_bits() != b.to_bits());
                }
            }
        }
        if avx2 {
            assert!(
                differ > 0,
                "{}: the AVX2 instances gave the plain code's values to the bit; are they called?",
                reference.name
            );
        }
    }
}
