//! The configuration phase: the header, then the joint frames read one at a
//! time into a configuration (in static memory on the firmware), and the
//! monitor built from it.

use super::error::Error;
use super::frames::{FrameError, Source};
use super::store::{build_from, MonitorStore};
use crate::monitor::config::ConfigRef;
use crate::monitor::MonitorConfig;
use crate::telemetry;
use crate::telemetry::config::{
    ConfigHeader, JointFrame, CONFIG_HEADER_FRAME_MAX, CONFIG_VERSION, JOINT_FRAME_MAX, MAX_JOINTS,
};

/// Reads the configuration header (the input's first frame).
pub fn read_header<R>(src: &mut Source<R>) -> Result<ConfigHeader, Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
{
    let mut buf = [0u8; CONFIG_HEADER_FRAME_MAX];
    let header: ConfigHeader = match src.next_frame(&mut buf) {
        Ok(Some(f)) => telemetry::decode(f).map_err(|_| Error::ConfigFrame)?,
        Err(FrameError::Read) => return Err(Error::Read),
        _ => return Err(Error::ConfigFrame),
    };
    let joints = usize::from(header.joints);
    if header.version != CONFIG_VERSION || !(1..=MAX_JOINTS).contains(&joints) {
        return Err(Error::ConfigFrame);
    }
    Ok(header)
}

/// Where the monitor configuration of `N` joints is built: the firmware
/// gives static storage (a configuration of 3 joints is about 1.5 KiB: on
/// the stack, under the monitor's construction, it would set the stack's
/// peak), the host anything.
// `repr(u8)`: the tag comes first and `Empty` is 0, so an empty store is
// all zeros and a static one goes to .bss, not to .data (whose image
// would take its size in flash).
#[derive(Default)]
#[allow(clippy::large_enum_variant)]
#[repr(u8)]
pub enum ConfigStore<const N: usize> {
    /// No configuration yet.
    #[default]
    Empty,
    /// A configuration.
    Held(MonitorConfig<N>),
}

/// Puts a configuration of `N` placeholder joints (overwritten by the
/// joint frames) and the default tuning in `store`, and returns it. Out of
/// line: the placeholder leaves the stack before the joint frames are read.
#[inline(never)]
fn placeholder_config<const N: usize>(
    store: &mut ConfigStore<N>,
) -> Result<&mut MonitorConfig<N>, Error> {
    let (panel, joint, tuning) = placeholder()?;
    *store = ConfigStore::Held(MonitorConfig {
        panels: [panel; N],
        joints: [joint; N],
        sensor: tuning.sensor,
        observer: tuning.observer,
        latch: tuning.latch,
        margin: tuning.margin,
    });
    match store {
        ConfigStore::Held(config) => Ok(config),
        ConfigStore::Empty => Err(Error::Config),
    }
}

/// A placeholder joint (a spring of `None` always builds) and the default
/// tuning ([`MonitorConfig::new`]'s).
#[inline(never)]
fn placeholder() -> Result<
    (
        crate::physics::chain::Panel<f32>,
        crate::monitor::JointConfig,
        MonitorConfig<0>,
    ),
    Error,
> {
    let (panel, joint) = JointFrame::default()
        .to_config()
        .map_err(|_| Error::Config)?;
    Ok((panel, joint, MonitorConfig::new([], [])))
}

/// Reads the `joints` joint frames that follow the header into the first
/// `joints` panels and joints of `config`, and the header's deadline and
/// latch into its tuning; [`Error::JointCount`] unless the header gives
/// `joints` joints, [`Error::ConfigFrame`] unless `config` has as many.
#[inline(never)]
fn read_joints<const M: usize, R>(
    header: &ConfigHeader,
    src: &mut Source<R>,
    config: &mut MonitorConfig<M>,
    joints: usize,
) -> Result<(), Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
{
    if usize::from(header.joints) != joints {
        return Err(Error::JointCount {
            expected: u8::try_from(joints).unwrap_or(u8::MAX),
            found: header.joints,
        });
    }
    let (Some(panels), Some(frames)) = (
        config.panels.get_mut(..joints),
        config.joints.get_mut(..joints),
    ) else {
        return Err(Error::ConfigFrame);
    };
    for (panel, joint) in panels.iter_mut().zip(frames) {
        read_joint(src, panel, joint)?;
    }
    config.margin.deadline_s = header.deadline_s;
    config.latch.physical = header.latch;
    Ok(())
}

/// Reads one joint frame and writes its panel and joint configuration.
/// Out of line: the frame buffer and the decoded frame are one joint's.
#[inline(never)]
fn read_joint<R>(
    src: &mut Source<R>,
    panel: &mut crate::physics::chain::Panel<f32>,
    joint: &mut crate::monitor::JointConfig,
) -> Result<(), Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
{
    let mut buf = [0u8; JOINT_FRAME_MAX];
    let frame: JointFrame = match src.next_frame(&mut buf) {
        Ok(Some(f)) => telemetry::decode(f).map_err(|_| Error::ConfigFrame)?,
        Err(FrameError::Read) => return Err(Error::Read),
        _ => return Err(Error::ConfigFrame),
    };
    (*panel, *joint) = frame.to_config().map_err(|_| Error::Config)?;
    Ok(())
}

/// The configuration phase of a replay, after [`read_header`]: reads the
/// joint frames into `config` and builds the monitor in `store`;
/// [`Error::JointCount`] when the header's joint count is not `N`. With
/// both stores in static memory the stack holds, in turn, one joint frame,
/// then the monitor's construction — never the configuration or two of
/// them at once.
pub fn configure<const N: usize, R>(
    header: &ConfigHeader,
    src: &mut Source<R>,
    config: &mut ConfigStore<N>,
    store: &mut MonitorStore<N>,
) -> Result<(), Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
{
    if usize::from(header.joints) != N {
        return Err(Error::JointCount {
            expected: u8::try_from(N).unwrap_or(u8::MAX),
            found: header.joints,
        });
    }
    let c = placeholder_config(config)?;
    read_joints(header, src, c, N)?;
    build_from(ConfigRef::of(c), store)
}
