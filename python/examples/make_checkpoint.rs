//! Writes the checkpoint an onboard identifier (`hsid::Identifier`, f64, the paper's
//! capacity) saves after it was fed a record: what a device exports for `hsid solve --state`
//! and `hsid.solve_checkpoint`. The Python tests run it.
//!
//! `make_checkpoint RECORD.csv UMIN UMAX SEGMENTS HOLD OUT.bin`: RECORD.csv has the columns
//! `u,y` under a header (lines starting with `#` are skipped); uniform knots with SEGMENTS
//! per path, horizons f = p = 10, a hold of HOLD samples of which the first half settles.

use std::process::ExitCode;

use hsid::{Identifier, Knots, MuZero, Settings};

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("make_checkpoint: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [record, umin, umax, segments, hold, out] = args.as_slice() else {
        return Err("usage: make_checkpoint RECORD.csv UMIN UMAX SEGMENTS HOLD OUT.bin".into());
    };
    let num = |s: &str| s.parse::<f64>().map_err(|e| format!("{s}: {e}"));
    let count = |s: &str| s.parse::<usize>().map_err(|e| format!("{s}: {e}"));
    let (umin, umax, segments, hold) = (num(umin)?, num(umax)?, count(segments)?, count(hold)?);
    let text = std::fs::read_to_string(record).map_err(|e| format!("{record}: {e}"))?;
    let knots = Knots::uniform(umin, umax, segments, segments).map_err(|e| e.to_string())?;
    let settings = Settings::new(
        knots,
        10,
        10,
        MuZero::Hold {
            len: hold,
            settle: hold / 2,
        },
    );
    let mut id = Box::new(Identifier::<f64, 14, 20>::new(settings).map_err(|e| e.to_string())?);
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let (u, y) = line
            .split_once(',')
            .ok_or_else(|| format!("{record}: line {line:?} is not u,y"))?;
        id.push(num(u)?, num(y)?);
    }
    let mut bytes = vec![0u8; hsid::checkpoint_capacity(14, 20, 8)];
    let len = id.save(&mut bytes).map_err(|e| e.to_string())?;
    std::fs::write(out, &bytes[..len]).map_err(|e| format!("{out}: {e}"))
}
