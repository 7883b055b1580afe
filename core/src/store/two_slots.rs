//! The store: a flash and the two slots' place on it.

use super::error::StoreError;
use super::flash::Flash;
use super::layout::{Region, Slots};

/// Two checkpoint slots on a flash (see the [module docs](super)).
#[derive(Debug)]
pub struct Store<F: Flash> {
    pub(super) flash: F,
    region: Region,
    pub(super) geometry: Slots,
}

impl<F: Flash> Store<F> {
    /// A store on `region` of `flash`; checks the geometry, reads nothing.
    pub fn new(flash: F, region: Region) -> Result<Self, StoreError<F::Error>> {
        let geometry = Slots::of::<F>(region)?;
        Ok(Self {
            flash,
            region,
            geometry,
        })
    }

    /// Largest payload a slot holds, in bytes.
    pub fn capacity(&self) -> usize {
        self.geometry.capacity()
    }

    /// The region the store uses.
    pub fn region(&self) -> Region {
        self.region
    }

    /// The flash.
    pub fn flash(&self) -> &F {
        &self.flash
    }

    /// The flash, mutably (a board's other uses of it; writing into the region voids the
    /// store's guarantees for the slot written).
    pub fn flash_mut(&mut self) -> &mut F {
        &mut self.flash
    }

    /// Gives the flash back.
    pub fn into_inner(self) -> F {
        self.flash
    }
}
