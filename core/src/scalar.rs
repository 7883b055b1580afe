//! The floating-point types the core runs on: `f32` (microcontrollers) and `f64` (desktop).

use nalgebra::RealField;

/// A real scalar the identification can run on. Implemented for `f32` and `f64`.
///
/// All arithmetic goes through [`RealField`] (and so through `libm` on targets without a
/// floating-point library), so the same code runs on a desktop and on a Cortex-M4F.
pub trait Real: RealField + Copy + Default + core::fmt::Debug {
    /// Machine epsilon.
    const EPS: Self;
    /// Zero, usable in constant expressions (static buffers).
    const ZERO: Self;
    /// One, usable in constant expressions.
    const ONE: Self;
    /// Converts from `f64` (rounding to nearest for `f32`).
    fn of(x: f64) -> Self;
    /// Converts to `f64` (exact for both implementations).
    fn to_f64(self) -> f64;
    /// Converts a count to the scalar type.
    fn of_usize(n: usize) -> Self {
        Self::of(n as f64)
    }
    /// `true` if the value is neither NaN nor infinite.
    fn finite(self) -> bool;
    /// Size of the little-endian encoding (4 or 8).
    const BYTES: usize;
    /// Writes the exact bit pattern, little-endian, into the first [`Self::BYTES`] bytes.
    /// Returns `false` (writing nothing) if `out` is too short.
    fn write_le(self, out: &mut [u8]) -> bool;
    /// Reads a value written by [`Real::write_le`]; `None` if `bytes` is too short.
    fn read_le(bytes: &[u8]) -> Option<Self>;
}

impl Real for f32 {
    const EPS: Self = f32::EPSILON;
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    fn of(x: f64) -> Self {
        x as f32
    }
    fn to_f64(self) -> f64 {
        self as f64
    }
    fn finite(self) -> bool {
        self.is_finite()
    }
    const BYTES: usize = 4;
    fn write_le(self, out: &mut [u8]) -> bool {
        match out.get_mut(..4) {
            Some(o) => {
                o.copy_from_slice(&self.to_bits().to_le_bytes());
                true
            }
            None => false,
        }
    }
    fn read_le(bytes: &[u8]) -> Option<Self> {
        let b: [u8; 4] = bytes.get(..4)?.try_into().ok()?;
        Some(f32::from_bits(u32::from_le_bytes(b)))
    }
}

impl Real for f64 {
    const EPS: Self = f64::EPSILON;
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    fn of(x: f64) -> Self {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
    fn finite(self) -> bool {
        self.is_finite()
    }
    const BYTES: usize = 8;
    fn write_le(self, out: &mut [u8]) -> bool {
        match out.get_mut(..8) {
            Some(o) => {
                o.copy_from_slice(&self.to_bits().to_le_bytes());
                true
            }
            None => false,
        }
    }
    fn read_le(bytes: &[u8]) -> Option<Self> {
        let b: [u8; 8] = bytes.get(..8)?.try_into().ok()?;
        Some(f64::from_bits(u64::from_le_bytes(b)))
    }
}
