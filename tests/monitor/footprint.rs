//! The monitor's RAM and its telemetry frames.

use super::*;

/// The RAM one `Monitor<3>` may take \[bytes\]: 4 KiB, the physical latch's
/// bookkeeping of its three joints (the tracker's bounce state and the
/// plunger's engagement, `docs/monitor.md` §4.1), and the three
/// rate-dependent terms of the core's one friction law (Stribeck excess and
/// rate, quadratic damping: 3 × `f32`) in each joint of the monitor's chain,
/// held at 0 on board, and each joint's own latch thresholds (a wing may
/// mix ideal, plunger and pawl latches: a `LatchConfig` of at most 60 B
/// per joint), and each joint's rest band near its ideal latch (the
/// reading that starts it and its timer: 2 × `f32`).
const MONITOR_3_BUDGET_B: usize = 4096 + 3 * 64 + 3 * 12 + 3 * 60 + 3 * 8;

#[test]
fn monitor_fits_in_its_ram_budget() {
    let size = std::mem::size_of::<Monitor<3>>();
    println!("size_of::<Monitor<3>>() = {size} bytes");
    println!(
        "size_of::<Monitor<2>>() = {} bytes",
        std::mem::size_of::<Monitor<2>>()
    );
    println!(
        "size_of::<Status<3>>() = {} bytes",
        std::mem::size_of::<Status<3>>()
    );
    let latch = std::mem::size_of::<deploywatch_core::monitor::LatchConfig>();
    assert!(latch <= 60, "LatchConfig: {latch} bytes");
    assert!(size <= MONITOR_3_BUDGET_B, "{size} bytes");
}

/// Every status of a T02 run goes through a telemetry frame and back
/// unchanged, within the frame size the firmware reserves.
#[test]
fn status_and_sample_frames_round_trip() {
    use deploywatch_core::telemetry::{decode, encode, sample_frame_max, status_frame_max};
    let mech = mechanism("seed001_T02");
    let cfg = monitor_config::<3>(&mech).unwrap();
    let (_, run) = simulate_run(&mech, &coulomb(&SEED001_FRICTION), 3);
    let mut m = Monitor::new(&cfg).unwrap();
    let mut buf = [0u8; status_frame_max(3)];
    let mut sbuf = [0u8; sample_frame_max(3)];
    let mut longest = 0;
    for sample in samples::<3>(&run).unwrap() {
        let status = *m.update(&sample);
        let frame = encode(&status, &mut buf).expect("status frame");
        longest = longest.max(frame.len());
        assert_eq!(
            frame.iter().filter(|b| **b == 0).count(),
            1,
            "COBS: one zero, the terminator"
        );
        let back: Status<3> = decode(frame).expect("decode");
        assert_eq!(back, status);
        let frame = encode(&sample, &mut sbuf).expect("sample frame");
        let back: Sample<3> = decode(frame).expect("decode");
        assert_eq!(back.t_s.to_bits(), sample.t_s.to_bits());
        assert_eq!(back.latch, sample.latch);
    }
    println!(
        "longest status frame {longest} of {} bytes",
        status_frame_max(3)
    );
    // A flipped bit is caught by the CRC.
    let status = *m.status();
    let frame = encode(&status, &mut buf).unwrap();
    let n = frame.len();
    frame[n / 2] ^= 0x10;
    if frame[n / 2] == 0 {
        frame[n / 2] = 0x01;
    }
    assert!(decode::<Status<3>>(&mut buf[..n]).is_err());
}
