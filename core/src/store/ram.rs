//! A flash in RAM that keeps the rules of real parts and can lose power on cue: for tests,
//! simulations and boards without a spare flash region.

use super::flash::Flash;

/// Why a [`RamFlash`] operation failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RamFlashError {
    /// The bytes or the page lie beyond the flash.
    Range,
    /// A write's offset or length is not a multiple of the program unit.
    Alignment,
    /// A write over bytes not erased since they were written (refused whole, as parts with
    /// ECC do).
    NotErased,
    /// The power was cut ([`RamFlash::cut_power`]) during or before this operation.
    PowerLost,
}

/// When to cut the power: after a number of programmed bytes and erased pages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PowerCut {
    /// Bytes still programmed in full before the cut.
    pub bytes: usize,
    /// Bits of the next byte that are programmed anyway, if the cut falls on a write (a torn
    /// byte: `old & (new | !torn_bits)`); 0 for a clean cut between bytes.
    pub torn_bits: u8,
    /// Erases that still complete before the cut.
    pub erases: usize,
    /// Whether an erase hit by the cut sets the first half of its page to `0xFF` (a torn
    /// erase) rather than nothing.
    pub torn_erase: bool,
}

/// Bytes programmed and pages erased since the flash was made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Wear {
    /// Bytes programmed.
    pub bytes: usize,
    /// Pages erased.
    pub erases: usize,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Power {
    On,
    Until(PowerCut),
    Off,
}

/// `N` bytes of flash in RAM with pages of `PAGE` bytes and a program unit of `WRITE` bytes.
/// Starts erased; writes refuse misaligned or non-erased targets; a [`PowerCut`] makes an
/// operation stop part-way and every later one fail until [`restore_power`](Self::restore_power).
#[derive(Clone, Debug)]
pub struct RamFlash<const N: usize, const PAGE: usize, const WRITE: usize> {
    bytes: [u8; N],
    power: Power,
    wear: Wear,
}

impl<const N: usize, const PAGE: usize, const WRITE: usize> Default for RamFlash<N, PAGE, WRITE> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize, const PAGE: usize, const WRITE: usize> RamFlash<N, PAGE, WRITE> {
    /// An erased flash with the power on.
    pub const fn new() -> Self {
        Self {
            bytes: [0xFF; N],
            power: Power::On,
            wear: Wear {
                bytes: 0,
                erases: 0,
            },
        }
    }

    /// The content.
    pub fn bytes(&self) -> &[u8; N] {
        &self.bytes
    }

    /// The content, to damage it on purpose (bit flips).
    pub fn bytes_mut(&mut self) -> &mut [u8; N] {
        &mut self.bytes
    }

    /// Arms a power cut.
    pub fn cut_power(&mut self, cut: PowerCut) {
        self.power = Power::Until(cut);
    }

    /// Powers up again (content as the cut left it).
    pub fn restore_power(&mut self) {
        self.power = Power::On;
    }

    /// Whether an armed cut has happened.
    pub fn power_lost(&self) -> bool {
        self.power == Power::Off
    }

    /// Bytes programmed and pages erased so far.
    pub fn wear(&self) -> Wear {
        self.wear
    }
}

impl<const N: usize, const PAGE: usize, const WRITE: usize> Flash for RamFlash<N, PAGE, WRITE> {
    const PAGE: usize = PAGE;
    const WRITE: usize = WRITE;
    type Error = RamFlashError;

    fn erase(&mut self, page: usize) -> Result<(), RamFlashError> {
        let start = page.checked_mul(PAGE).ok_or(RamFlashError::Range)?;
        let end = start.checked_add(PAGE).ok_or(RamFlashError::Range)?;
        let dst = self.bytes.get_mut(start..end).ok_or(RamFlashError::Range)?;
        match &mut self.power {
            Power::Off => return Err(RamFlashError::PowerLost),
            Power::Until(cut) if cut.erases == 0 => {
                if cut.torn_erase {
                    dst.iter_mut().take(PAGE / 2).for_each(|b| *b = 0xFF);
                }
                self.power = Power::Off;
                return Err(RamFlashError::PowerLost);
            }
            Power::Until(cut) => cut.erases -= 1,
            Power::On => {}
        }
        dst.fill(0xFF);
        self.wear.erases += 1;
        Ok(())
    }

    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), RamFlashError> {
        if WRITE == 0 || !offset.is_multiple_of(WRITE) || !data.len().is_multiple_of(WRITE) {
            return Err(RamFlashError::Alignment);
        }
        let end = offset.checked_add(data.len()).ok_or(RamFlashError::Range)?;
        let dst = self
            .bytes
            .get_mut(offset..end)
            .ok_or(RamFlashError::Range)?;
        if self.power == Power::Off {
            return Err(RamFlashError::PowerLost);
        }
        if dst.iter().any(|&b| b != 0xFF) {
            return Err(RamFlashError::NotErased);
        }
        for (d, &s) in dst.iter_mut().zip(data) {
            if let Power::Until(cut) = &mut self.power {
                if cut.bytes == 0 {
                    *d &= s | !cut.torn_bits;
                    self.power = Power::Off;
                    return Err(RamFlashError::PowerLost);
                }
                cut.bytes -= 1;
            }
            *d = s;
            self.wear.bytes += 1;
        }
        Ok(())
    }

    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), RamFlashError> {
        if self.power == Power::Off {
            return Err(RamFlashError::PowerLost);
        }
        let end = offset.checked_add(buf.len()).ok_or(RamFlashError::Range)?;
        let src = self.bytes.get(offset..end).ok_or(RamFlashError::Range)?;
        buf.copy_from_slice(src);
        Ok(())
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    type F = RamFlash<64, 16, 8>;

    #[test]
    fn keeps_the_rules_of_flash() {
        let mut f = F::new();
        assert_eq!(f.write(4, &[0; 8]), Err(RamFlashError::Alignment));
        assert_eq!(f.write(0, &[0; 4]), Err(RamFlashError::Alignment));
        assert_eq!(f.write(64, &[0; 8]), Err(RamFlashError::Range));
        assert_eq!(f.erase(4), Err(RamFlashError::Range));
        f.write(8, &[0xF0; 8]).unwrap();
        // Even a write that would only clear more bits is refused.
        assert_eq!(f.write(8, &[0x00; 8]), Err(RamFlashError::NotErased));
        f.erase(0).unwrap();
        assert_eq!(f.bytes()[..16], [0xFF; 16]);
        f.write(8, &[0x00; 8]).unwrap();
        assert_eq!(
            f.wear(),
            Wear {
                bytes: 16,
                erases: 1
            }
        );
    }

    #[test]
    fn a_cut_tears_the_write_in_progress_and_stops_everything_after() {
        let mut f = F::new();
        f.cut_power(PowerCut {
            bytes: 3,
            torn_bits: 0x0F,
            erases: 0,
            torn_erase: false,
        });
        assert_eq!(f.write(0, &[0x00; 8]), Err(RamFlashError::PowerLost));
        assert_eq!(f.bytes()[..5], [0x00, 0x00, 0x00, 0xF0, 0xFF]);
        let mut b = [0u8; 1];
        assert_eq!(f.read(0, &mut b), Err(RamFlashError::PowerLost));
        f.restore_power();
        f.write(16, &[0x11; 16]).unwrap();
        f.cut_power(PowerCut {
            bytes: 0,
            torn_bits: 0,
            erases: 0,
            torn_erase: true,
        });
        assert_eq!(f.erase(1), Err(RamFlashError::PowerLost));
        assert_eq!(f.bytes()[16..32], [[0xFF; 8], [0x11; 8]].concat()[..]);
    }
}
