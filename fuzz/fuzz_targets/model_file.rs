//! The model-file reader on arbitrary bytes. A file that is read must write back to text that
//! reads to the same model (bit for bit), and that text must be stable.
#![no_main]

use hsid_host::model_file::ModelFile;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(model) = ModelFile::from_json_str("fuzz.json", text) else {
        return;
    };
    let written = model
        .to_json_string("fuzz.json")
        .expect("a model that was read validates and writes");
    let back = ModelFile::from_json_str("fuzz.json", &written).expect("written text reads");
    assert_eq!(back, model, "model file round trip changed the model");
    let rewritten = back.to_json_string("fuzz.json").expect("writes again");
    assert_eq!(rewritten, written, "model file text is not stable");
});
