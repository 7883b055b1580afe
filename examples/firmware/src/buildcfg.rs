//! The identification's sizes, chosen at build time: `HSID_FW_SEGMENTS` (uniform segments per
//! path), `HSID_FW_F` and `HSID_FW_P` (future and past horizons), read by `option_env!` and
//! parsed here at compile time. Unset, they are the paper's configuration (7, 10, 10);
//! `scripts/firmware-fit.sh` builds the firmware for several to tabulate what fits where.
//! A value that is not a decimal number fails the build with a message naming the variable.

/// `value` parsed as a decimal `usize`, or `default` if it is `None`. Fails the build (a
/// panic in constant evaluation, with `name` as the message) if `value` is empty, not all
/// digits, or overflows.
pub const fn number(name: &str, value: Option<&str>, default: usize) -> usize {
    let Some(text) = value else {
        return default;
    };
    let bytes = text.as_bytes();
    if bytes.is_empty() {
        panic_bad(name);
    }
    let mut n: usize = 0;
    let mut i = 0;
    while i < bytes.len() {
        let d = bytes[i];
        if !d.is_ascii_digit() {
            panic_bad(name);
        }
        n = match n.checked_mul(10) {
            Some(v) => match v.checked_add((d - b'0') as usize) {
                Some(v) => v,
                None => panic_bad(name),
            },
            None => panic_bad(name),
        };
        i += 1;
    }
    n
}

/// Stops the build: the variable `name` does not hold a decimal number. Reached in constant
/// evaluation only (the sizes are constants), so it is a compile error naming the variable,
/// never a run-time panic.
const fn panic_bad(name: &str) -> ! {
    panic!("{}", name)
}
