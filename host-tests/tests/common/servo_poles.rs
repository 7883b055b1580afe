//! The closed-loop servo's poles, shared by the closed-loop tests: the simulator's true upper
//! pole and a model's pole with the largest imaginary part.

use hsid_host::identify::HostModel;
use hsid_host::numerics::poly::roots;

/// The true plant's upper pole (`G(q)` of the simulator, `1 − 1.8858 q⁻¹ + 0.9048 q⁻²`).
pub fn true_pole() -> (f64, f64) {
    roots(&[1.0, -1.8858, 0.9048]).unwrap()[0]
}

/// The pole with the largest imaginary part.
pub fn upper_pole(m: &HostModel) -> (f64, f64) {
    m.poles().into_iter().fold(
        (f64::NAN, f64::NEG_INFINITY),
        |a, p| if p.1 > a.1 { p } else { a },
    )
}
