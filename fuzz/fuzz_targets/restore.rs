//! `Identifier::restore` on arbitrary bytes, in the `f32` and `f64` configurations with plain
//! and compensated sums. A checkpoint that restores must save back to the same bytes, restore
//! again to the same state and solve (to a model or an error) without panicking; the host's
//! header reader must agree that it is a checkpoint.
#![no_main]

use hsid::{Compensated, Identifier, Plain, Real, Summation};
use libfuzzer_sys::fuzz_target;

/// The paper's capacity class on the host (16 channels, 24 block rows, horizon 12).
const M: usize = 16;
const K: usize = 24;

fn check<T: Real, S: Summation<T, M, K>>(data: &[u8]) {
    let Ok(id) = Identifier::<T, M, K, S>::restore(data) else {
        return;
    };
    let len = id.checkpoint_len();
    assert!(len <= data.len(), "restored from fewer bytes than it saves");
    let mut buf = vec![0u8; len];
    assert_eq!(id.save(&mut buf), Ok(len));
    assert_eq!(buf, data[..len], "restore then save changed the bytes");
    let again = Identifier::<T, M, K, S>::restore(&buf).expect("a saved checkpoint restores");
    let mut buf2 = vec![0u8; len];
    assert_eq!(again.save(&mut buf2), Ok(len));
    assert_eq!(buf, buf2, "second round trip differs");
    assert!(
        hsid_host::identify::checkpoint_header(data).is_ok(),
        "the host's header reader refuses a checkpoint the core restores"
    );
    let mut ws = vec![T::ZERO; id.workspace_len()];
    let _ = id.solve(&mut ws);
}

fuzz_target!(|data: &[u8]| {
    check::<f32, Plain>(data);
    check::<f64, Plain>(data);
    check::<f32, Compensated>(data);
    check::<f64, Compensated>(data);
});
