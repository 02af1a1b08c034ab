//! Tests of the monitor built in its store, and of configurations refused.

use super::*;
use crate::monitor::Sample;
use crate::monitor::{ConfigError, JointParam, TuningParam};
use crate::telemetry::config::{ConfigHeader, CONFIG_VERSION, MAX_JOINTS};
use crate::telemetry::replay::{configure, ConfigStore, Source, STATUS_FRAME_MAX};
use crate::ChainError;

/// A chain of `N` equal panels on linear springs, stowed at 90°, 100°, …
fn config<const N: usize>() -> MonitorConfig<N> {
    crate::monitor::estimator::example_config()
}

/// A deployment at 100 Hz: every joint opens from its stowed angle to
/// its latch in 1.5 s, then holds with the switch closed.
fn sample<const N: usize>(config: &MonitorConfig<N>, k: usize) -> Sample<N> {
    let t = k as f32 * 0.01;
    let x = (1.0 - t / 1.5).max(0.0);
    Sample::new(
        t,
        core::array::from_fn(|j| config.joints[j].stowed_deg * x * x),
        [x == 0.0; N],
    )
}

/// The status frames of `monitor` over samples `from..to`, two
/// prediction slices after each.
fn frames<const N: usize>(
    monitor: &mut Monitor<N>,
    config: &MonitorConfig<N>,
    from: usize,
    to: usize,
) -> Vec<u8> {
    let mut all = Vec::new();
    let mut out = [0u8; STATUS_FRAME_MAX];
    for k in from..to {
        monitor.update(&sample(config, k));
        monitor.learn_or_predict();
        monitor.learn_or_predict();
        let n = status_frame(monitor, &mut out).expect("status frame");
        all.extend_from_slice(&out[..n]);
    }
    all
}

/// The frames of a fresh monitor of `c`, and of one built in `store`
/// after it held a used monitor (used for `used` samples).
fn rebuilt<const N: usize>(
    c: &MonitorConfig<N>,
    store: &mut MonitorStore<N>,
    used: usize,
) -> (Vec<u8>, Vec<u8>) {
    let fresh = frames(&mut Monitor::new(c).expect("config"), c, 0, 200);
    let m = store.slot(ConfigRef::of(c)).expect("a monitor");
    frames(m, c, 0, used);
    build(c, store).expect("build");
    let m = store.monitor().expect("built");
    (frames(m, c, 0, 200), fresh)
}

#[test]
fn a_monitor_built_in_its_slot_answers_as_a_new_one() {
    // Built in an empty slot, and in one holding a used monitor
    // (used for an odd number of samples: stopped mid-way through the
    // joints' turns), for several joint counts up to the most.
    let c3 = config::<3>();
    let mut store = MonitorStore::<3>::Empty;
    build(&c3, &mut store).expect("build");
    let fresh3 = frames(&mut Monitor::new(&c3).expect("config"), &c3, 0, 200);
    let m = store.monitor().expect("3 joints");
    assert_eq!(m.clone().status().joints.len(), 3);
    assert_eq!(frames(m, &c3, 0, 200), fresh3);
    for used in [137, 91] {
        let (built, fresh) = rebuilt(&c3, &mut store, used);
        assert_eq!(built, fresh);
    }
    let (built, fresh) = rebuilt(&config::<1>(), &mut MonitorStore::Empty, 77);
    assert_eq!(built, fresh);
    let (built, fresh) = rebuilt(&config::<6>(), &mut MonitorStore::Empty, 137);
    assert_eq!(built, fresh);
    let (built, fresh) = rebuilt(&config::<MAX_JOINTS>(), &mut MonitorStore::Empty, 91);
    assert_eq!(built, fresh);
}

#[test]
fn a_configuration_of_another_joint_count_is_refused_by_name() {
    let c2 = config::<2>();
    let mut m = Monitor::new(&c2).expect("config");
    frames(&mut m, &c2, 0, 80);
    let mut before = m.clone();
    assert_eq!(
        m.reset_from(ConfigRef::of(&config::<3>())),
        Err(ConfigError::JointCount {
            expected: 2,
            found: 3
        })
    );
    assert_eq!(
        frames(&mut m, &c2, 80, 200),
        frames(&mut before, &c2, 80, 200)
    );
    // The replay's configuration: a header of 3 joints to a store of 6.
    let header = ConfigHeader {
        version: CONFIG_VERSION,
        joints: 3,
        deadline_s: 20.0,
        latch: None,
    };
    let mut src = Source::new(|_: &mut [u8]| Ok(0));
    let mut config = ConfigStore::<6>::Empty;
    let mut store = MonitorStore::<6>::Empty;
    assert_eq!(
        configure(&header, &mut src, &mut config, &mut store),
        Err(Error::JointCount {
            expected: 6,
            found: 3
        })
    );
    assert_eq!(store.joints(), 0);
}

#[test]
fn a_rejected_configuration_leaves_the_monitor_as_it_was() {
    let c = config::<3>();
    let mut m = Monitor::new(&c).expect("config");
    frames(&mut m, &c, 0, 80);
    let mut before = m.clone();
    let mut bad_panel = c;
    bad_panel.panels[1].mass_kg = 0.0;
    assert_eq!(
        m.reset(&bad_panel),
        Err(ConfigError::Chain(ChainError::BadPanel { index: 1 }))
    );
    let mut bad_joint = c;
    bad_joint.joints[2].prior.coulomb_sd_nm = 0.0;
    assert_eq!(
        m.reset(&bad_joint),
        Err(ConfigError::Joint {
            index: 2,
            what: JointParam::CoulombPriorSd
        })
    );
    let mut bad_tuning = c;
    bad_tuning.sensor.encoder_sd_deg = -1.0;
    assert_eq!(
        m.reset(&bad_tuning),
        Err(ConfigError::Parameter(TuningParam::EncoderSdDeg))
    );
    assert_eq!(
        frames(&mut m, &c, 80, 200),
        frames(&mut before, &c, 80, 200)
    );
}

#[test]
fn reset_reports_what_validate_reports() {
    // A bad joint before a bad tuning parameter, as `validate` orders them.
    let mut c = config::<3>();
    c.joints[1].stowed_deg = f32::NAN;
    c.observer.gate_sigma = 0.0;
    let mut m = Monitor::new(&config::<3>()).expect("config");
    assert_eq!(m.reset(&c).err(), c.validate().err());
    c.joints[1].stowed_deg = 90.0;
    assert_eq!(m.reset(&c).err(), c.validate().err());
    c.observer = config::<3>().observer;
    assert_eq!(m.reset(&c), Ok(()));
}
