//! The telemetry frame decoder (COBS, postcard, CRC-32C) on an arbitrary
//! byte stream, as a ground station receives it (docs/robustness.md).
//!
//! Oracle: never a panic; a frame that decodes re-encodes within the
//! documented maximum frame size into a frame that decodes to the same
//! bytes again.
#![no_main]

use deploywatch_core::monitor::{Sample, Status};
use deploywatch_core::telemetry::{self, sample_frame_max, status_frame_max};
use libfuzzer_sys::fuzz_target;
use serde::{de::DeserializeOwned, Serialize};

fuzz_target!(|data: &[u8]| {
    // A receiver splits the stream at every 0x00 and decodes each piece.
    for piece in data.split(|&b| b == 0) {
        check::<Sample<3>>(piece, sample_frame_max(3));
        check::<Status<3>>(piece, status_frame_max(3));
        check::<Sample<1>>(piece, sample_frame_max(1));
        check::<Status<4>>(piece, status_frame_max(4));
    }
    // And the whole input as one frame (with zeros inside).
    check::<Status<3>>(data, status_frame_max(3));
});

fn check<T: Serialize + DeserializeOwned>(frame: &[u8], max: usize) {
    let mut buf = frame.to_vec();
    let Ok(value) = telemetry::decode::<T>(&mut buf) else {
        return;
    };
    let mut out = vec![0u8; max];
    let len = telemetry::encode(&value, &mut out)
        .unwrap_or_else(|e| panic!("a decoded value does not re-encode in {max} bytes: {e}"))
        .len();
    let first = out[..len].to_vec();
    let mut again = first.clone();
    let value2: T = telemetry::decode(&mut again)
        .unwrap_or_else(|e| panic!("re-encoded frame does not decode: {e}"));
    let mut out2 = vec![0u8; max];
    let len2 = telemetry::encode(&value2, &mut out2)
        .expect("second encode")
        .len();
    assert_eq!(&out2[..len2], &first[..], "encode-decode-encode differs");
}
