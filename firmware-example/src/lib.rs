//! The replay protocol of the deploywatch example firmware, shared by the
//! firmware (on the MCU, `src/main.rs`) and the host tool (`host/`), so that
//! both run the very same code on the same frames.
//!
//! # Files
//! - Input: a [`Header`] frame, then one [`Sample`] frame per sample of a
//!   recorded run, in time order.
//! - Output: one [`Status`] frame per input sample.
//!
//! Every frame is a postcard message, COBS-encoded and ended by a `0x00`
//! byte (`postcard::to_slice_cobs`), at most [`MAX_FRAME`] bytes long. The
//! stream is therefore self-delimiting: a reader resynchronises on the next
//! `0x00`, and a file can be cut or concatenated at frame boundaries.
//!
//! # Bit-identity
//! The firmware computes in `f32` with `libm` (see `deploywatch_core::real`),
//! exactly as this crate does on the host, so the output file of a QEMU run is
//! byte-for-byte the file that `deploywatch-replay run` writes on the host.
//!
//! # Provisional payload
//! Until the on-board `Monitor` lands in `deploywatch-core`, [`Replay::step`]
//! evaluates the chain model itself: the joint accelerations of the seed 001
//! T01 mechanism at the recorded angles, with rates from a backward
//! difference. The framing, the files and the comparison stay the same when
//! `Monitor::update` replaces it.
#![no_std]
#![deny(missing_docs)]
#![forbid(unsafe_code)]

use deploywatch_core::{
    Chain, ChainState, Friction, GlobalEffects, Joint, JointEffects, Mode, Panel, Real, Spring,
    TapePoints,
};
use postcard::accumulator::{CobsAccumulator, FeedResult};
use serde::{Deserialize, Serialize};

/// Number of joints of the replayed mechanism.
pub const JOINTS: usize = 3;

/// Version of the frame format, carried in the [`Header`].
pub const FORMAT_VERSION: u16 = 1;

/// Largest COBS-encoded frame, sentinel included [bytes]. The largest
/// message, a [`Status`], is at most 1 + 4·(1 + 2·3) = 29 bytes of postcard;
/// COBS adds at most one byte per 254 plus the sentinel.
pub const MAX_FRAME: usize = 64;

/// The first frame of an input file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Header {
    /// [`FORMAT_VERSION`] of the writer.
    pub version: u16,
    /// Number of joints in every [`Sample`]; must be [`JOINTS`].
    pub joints: u8,
}

impl Header {
    /// The header this crate writes and accepts.
    pub const CURRENT: Header = Header {
        version: FORMAT_VERSION,
        joints: JOINTS as u8,
    };
}

/// One recorded sample of a run (a row of the run CSV).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Time since release [s].
    pub t_s: f32,
    /// Joint angles [deg].
    pub phi_deg: [f32; JOINTS],
    /// Latch switch of each joint: `true` once latched.
    pub latch: [bool; JOINTS],
}

/// What the firmware reports for one sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Status {
    /// Time of the sample [s].
    pub t_s: f32,
    /// `true` when the model could be evaluated; `false` leaves the other
    /// fields at NaN.
    pub ok: bool,
    /// Joint rates, backward difference of the angles [rad/s].
    pub phi_dot_rad_s: [f32; JOINTS],
    /// Model joint accelerations at the recorded state [rad/s²].
    pub accel_rad_s2: [f32; JOINTS],
}

/// Why a replay stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// Reading the input failed.
    Read,
    /// Writing the output failed.
    Write,
    /// A frame did not decode (bad COBS or postcard, or longer than [`MAX_FRAME`]).
    Frame {
        /// 0-based index of the frame in the input (the header is frame 0).
        index: u32,
    },
    /// The input does not start with [`Header::CURRENT`].
    Header,
    /// The input ends inside a frame (no `0x00` after the last bytes).
    Truncated,
    /// The built-in mechanism could not be built.
    Model,
}

impl Error {
    /// A short description, for logs that cannot format (defmt).
    pub fn as_str(&self) -> &'static str {
        match self {
            Error::Read => "cannot read the input",
            Error::Write => "cannot write the output",
            Error::Frame { .. } => "a frame does not decode",
            Error::Header => "the input does not start with a version-1 header for 3 joints",
            Error::Truncated => "the input ends inside a frame",
            Error::Model => "the built-in mechanism is invalid",
        }
    }
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Frame { index } => write!(f, "frame {index} does not decode"),
            other => f.write_str(other.as_str()),
        }
    }
}

impl core::error::Error for Error {}

/// The seed 001 T01 mechanism (`data/mechanisms/seed001_T01.toml`) in `f32`:
/// three 0.8 m panels on tape-spring hinges TS-1 ×3, TS-2 ×2, TS-3 ×2.
pub fn seed001_t01() -> Result<Chain<f32, JOINTS>, Error> {
    let panel = Panel {
        length_m: 0.8,
        mass_kg: 3.5,
        com_m: 0.4,
        inertia_kgm2: 0.27,
    };
    let tape = |a: (f32, f32), b: (f32, f32), d: (f32, f32), m_90: f32, c_180: f32| TapePoints {
        a,
        b,
        d,
        m_90,
        c_180,
    };
    let ts1 = tape((1.10, 69.39), (1.10, 1.50), (0.52, 37.0), 1.20, 2.32);
    let ts2 = tape((1.26, 58.20), (1.28, 0.86), (0.65, 26.0), 0.80, 1.46);
    let ts3 = tape((1.08, 33.43), (1.15, 0.46), (0.29, 11.07), 0.385, 0.74);
    let joint = |stowed_deg: f32, spring: Spring<f32>| Joint {
        stowed_rad: stowed_deg.to_radians(),
        spring,
        friction: Friction::default(),
        effects: JointEffects::default(),
    };
    let spring = |p: &TapePoints<f32>, count: f32| Spring::tape(p, count).map_err(|_| Error::Model);
    let joints = [
        joint(-90.0, spring(&ts1, 3.0)?),
        joint(180.0, spring(&ts2, 2.0)?),
        joint(-180.0, spring(&ts3, 2.0)?),
    ];
    Chain::new([panel; JOINTS], joints, GlobalEffects::default()).map_err(|_| Error::Model)
}

/// The per-sample computation, identical on the MCU and on the host.
pub struct Replay {
    chain: Chain<f32, JOINTS>,
    /// Time [s] and angles [rad] of the previous sample.
    prev: Option<(f32, [f32; JOINTS])>,
}

impl Replay {
    /// A replay of the built-in mechanism, before the first sample.
    pub fn new() -> Result<Self, Error> {
        Ok(Replay {
            chain: seed001_t01()?,
            prev: None,
        })
    }

    /// Processes one sample.
    pub fn step(&mut self, s: &Sample) -> Status {
        let mut phi = [0.0f32; JOINTS];
        for (p, d) in phi.iter_mut().zip(s.phi_deg.iter()) {
            *p = Real::to_radians(*d);
        }
        let mut phi_dot = [0.0f32; JOINTS];
        if let Some((t0, phi0)) = self.prev {
            let dt = s.t_s - t0;
            if dt > 0.0 {
                for j in 0..JOINTS {
                    phi_dot[j] = (phi[j] - phi0[j]) / dt;
                }
            }
        }
        self.prev = Some((s.t_s, phi));
        let mode = Mode {
            latched: s.latch,
            ..Mode::default()
        };
        let x = ChainState { phi, phi_dot };
        match self.chain.acceleration(&x, &mode) {
            Ok(accel_rad_s2) => Status {
                t_s: s.t_s,
                ok: true,
                phi_dot_rad_s: phi_dot,
                accel_rad_s2,
            },
            Err(_) => Status {
                t_s: s.t_s,
                ok: false,
                phi_dot_rad_s: [f32::NAN; JOINTS],
                accel_rad_s2: [f32::NAN; JOINTS],
            },
        }
    }
}

/// Encodes one message as a COBS frame (sentinel included) into `buf`.
pub fn encode<'b, T: Serialize>(value: &T, buf: &'b mut [u8; MAX_FRAME]) -> Option<&'b [u8]> {
    postcard::to_slice_cobs(value, buf).ok().map(|b| &*b)
}

/// Decodes one COBS frame (its `0x00` optional) in place.
pub fn decode<T: serde::de::DeserializeOwned>(frame: &mut [u8]) -> Option<T> {
    postcard::from_bytes_cobs(frame).ok()
}

/// Size of the read buffer of [`run`] [bytes].
pub const READ_CHUNK: usize = 256;

/// Replays a whole input stream: reads it with `read` (like
/// `std::io::Read::read`: `Ok(0)` at the end), runs [`Replay::step`] on every
/// sample and hands each [`Status`] frame to `write`. Returns the number of
/// samples.
pub fn run<R, W>(mut read: R, mut write: W) -> Result<u32, Error>
where
    R: FnMut(&mut [u8]) -> Result<usize, ()>,
    W: FnMut(&[u8]) -> Result<(), ()>,
{
    let mut replay: Option<Replay> = None;
    let mut acc = CobsAccumulator::<MAX_FRAME>::new();
    let mut chunk = [0u8; READ_CHUNK];
    let mut out = [0u8; MAX_FRAME];
    let mut index: u32 = 0;
    let mut pending = false;
    loop {
        let n = read(&mut chunk).map_err(|_| Error::Read)?;
        if n == 0 {
            break;
        }
        let mut window = chunk.get(..n).ok_or(Error::Read)?;
        while !window.is_empty() {
            window = match replay.as_mut() {
                None => match acc.feed::<Header>(window) {
                    FeedResult::Consumed => {
                        pending = true;
                        break;
                    }
                    FeedResult::OverFull(_) | FeedResult::DeserError(_) => {
                        return Err(Error::Header);
                    }
                    FeedResult::Success { data, remaining } => {
                        if data != Header::CURRENT {
                            return Err(Error::Header);
                        }
                        replay = Some(Replay::new()?);
                        index += 1;
                        remaining
                    }
                },
                Some(r) => match acc.feed::<Sample>(window) {
                    FeedResult::Consumed => {
                        pending = true;
                        break;
                    }
                    FeedResult::OverFull(_) | FeedResult::DeserError(_) => {
                        return Err(Error::Frame { index });
                    }
                    FeedResult::Success { data, remaining } => {
                        let status = r.step(&data);
                        let frame = encode(&status, &mut out).ok_or(Error::Write)?;
                        write(frame).map_err(|_| Error::Write)?;
                        index += 1;
                        remaining
                    }
                },
            };
            pending = false;
        }
    }
    if replay.is_none() {
        return Err(Error::Header);
    }
    if pending {
        return Err(Error::Truncated);
    }
    Ok(index - 1)
}
