//! The replay's sample and status frames for a joint count known at run
//! time, up to [`MAX_JOINTS`]: the replay loop and the serial link read
//! and write them without being generic over the joint count, with the
//! bytes of [`Sample<N>`] and [`Status<N>`] on the wire.
//!
//! postcard writes a struct as its fields in order and a tuple (the
//! arrays, `crate::monitor::serde_array`) as its elements, neither with a
//! length: a [`StatusView`] writes exactly the bytes of the `Status<n>` it
//! views. A sample's payload is fixed-size — the time and `n` angles as
//! `f32` little-endian, then `n` switches as one byte each (0 or 1), then
//! the CRC-32C of those bytes — and [`CountedSample::decode`] reads it
//! without serde: exactly the frames that
//! [`telemetry::decode`](super::decode) reads as a `Sample<n>` decode, to
//! the same values, and the others fail with the same error (the tests
//! compare the two on every one-byte corruption of a frame). postcard's
//! generic reader, compiled for this one frame type, costs the firmware
//! more flash than this reader (`scripts/firmware.sh size` measures the
//! builds).

use serde::ser::{SerializeStruct, SerializeTuple, Serializer};
use serde::Serialize;

use super::config::MAX_JOINTS;
use super::{TelemetryError, CRC};
use crate::monitor::status::JointStatus;
use crate::monitor::{Sample, Status};

/// A [`Sample`] of `joints` joints, at most [`MAX_JOINTS`], the
/// count known at run time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CountedSample {
    /// Time stamp \[s\].
    pub t_s: f32,
    /// Encoder angle of each joint \[deg\], the first `joints` in use (the
    /// others 0).
    pub phi_deg: [f32; MAX_JOINTS],
    /// Latch switch of each joint (true = closed), the first `joints` in
    /// use (the others open).
    pub latch: [bool; MAX_JOINTS],
    /// Joints in use.
    pub joints: usize,
}

impl CountedSample {
    /// `sample` as a counted sample; `None` when it has more than
    /// [`MAX_JOINTS`] joints.
    pub fn of<const N: usize>(sample: &Sample<N>) -> Option<Self> {
        let mut counted = CountedSample::empty(N)?;
        counted
            .phi_deg
            .iter_mut()
            .zip(&sample.phi_deg)
            .for_each(|(d, s)| *d = *s);
        counted
            .latch
            .iter_mut()
            .zip(&sample.latch)
            .for_each(|(d, s)| *d = *s);
        counted.t_s = sample.t_s;
        Some(counted)
    }

    /// The sample as a [`Sample<N>`]; `None` unless it has `N` joints.
    #[inline(always)]
    pub fn to_sample<const N: usize>(&self) -> Option<Sample<N>> {
        (self.joints == N).then(|| {
            Sample::new(
                self.t_s,
                core::array::from_fn(|j| self.phi_deg.get(j).copied().unwrap_or(0.0)),
                core::array::from_fn(|j| self.latch.get(j).copied().unwrap_or(false)),
            )
        })
    }

    /// Reads one frame of a sample of `joints` joints, as
    /// [`telemetry::decode`](super::decode) reads a `Sample<joints>`: the
    /// same frames decode, to the same values, and the others fail with the
    /// same error (a payload too short for the sample and its CRC, or a
    /// switch byte other than 0 or 1: [`TelemetryError::BadPayload`]; then
    /// a CRC that does not match: [`TelemetryError::BadCrc`]; bytes after
    /// the CRC are ignored). `frame` is decoded in place. A `joints` over
    /// [`MAX_JOINTS`] is [`TelemetryError::BadPayload`].
    #[inline(never)]
    pub fn decode(frame: &mut [u8], joints: usize) -> super::Result<Self> {
        let payload = super::cobs_payload(frame)?;
        let mut sample = CountedSample::empty(joints).ok_or(TelemetryError::BadPayload)?;
        let floats = 4 * (1 + joints);
        let body = payload
            .get(..floats + joints)
            .ok_or(TelemetryError::BadPayload)?;
        let crc = word_at(payload, floats + joints).ok_or(TelemetryError::BadPayload)?;
        let t = word_at(body, 0).ok_or(TelemetryError::BadPayload)?;
        sample.t_s = f32::from_bits(t);
        for (j, phi) in sample.phi_deg.iter_mut().take(joints).enumerate() {
            let word = word_at(body, 4 * (1 + j)).ok_or(TelemetryError::BadPayload)?;
            *phi = f32::from_bits(word);
        }
        let switches = body.get(floats..).unwrap_or_default();
        for (closed, byte) in sample.latch.iter_mut().zip(switches) {
            *closed = match byte {
                0 => false,
                1 => true,
                _ => return Err(TelemetryError::BadPayload),
            };
        }
        if CRC.checksum(body) != crc {
            return Err(TelemetryError::BadCrc);
        }
        Ok(sample)
    }

    /// A sample of `joints` joints at time 0, every reading 0 and every
    /// switch open; `None` over [`MAX_JOINTS`].
    fn empty(joints: usize) -> Option<Self> {
        (joints <= MAX_JOINTS).then_some(CountedSample {
            t_s: 0.0,
            phi_deg: [0.0; MAX_JOINTS],
            latch: [false; MAX_JOINTS],
            joints,
        })
    }
}

/// The 4 bytes at `at` of `bytes` as a little-endian word (postcard's
/// `f32` and the frame's CRC).
fn word_at(bytes: &[u8], at: usize) -> Option<u32> {
    let word: [u8; 4] = bytes.get(at..at.checked_add(4)?)?.try_into().ok()?;
    Some(u32::from_le_bytes(word))
}

/// A [`Status`] of any joint count, borrowed: it serializes as the
/// `Status<N>` it views.
#[derive(Clone, Copy, Debug)]
pub struct StatusView<'a> {
    /// Time stamp of the last sample used \[s\].
    pub t_s: f32,
    /// Samples used so far.
    pub samples: u32,
    /// Per joint.
    pub joints: &'a [JointStatus],
}

impl<'a> StatusView<'a> {
    /// The view of `status`.
    pub fn of<const N: usize>(status: &'a Status<N>) -> Self {
        StatusView {
            t_s: status.t_s,
            samples: status.samples,
            joints: &status.joints,
        }
    }

    /// Writes the status as one frame into `buf` (as
    /// [`telemetry::encode`](super::encode) writes the `Status<N>` it
    /// views) and returns the frame's length.
    #[inline(never)]
    pub fn encode(&self, buf: &mut [u8]) -> super::Result<usize> {
        super::encode(self, buf).map(|f| f.len())
    }
}

impl Serialize for StatusView<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("Status", 3)?;
        st.serialize_field("t_s", &self.t_s)?;
        st.serialize_field("samples", &self.samples)?;
        st.serialize_field("joints", &Tuple(self.joints))?;
        st.end()
    }
}

/// A slice serialized as a tuple (no length), as `serde_array` writes an
/// array.
struct Tuple<'a, T>(&'a [T]);

impl<T: Serialize> Serialize for Tuple<'_, T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut t = s.serialize_tuple(self.0.len())?;
        for x in self.0 {
            t.serialize_element(x)?;
        }
        t.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::monitor::faults::{Fault, FaultFlags};
    use crate::monitor::latch::LatchState;
    use crate::monitor::predictor::Prediction;
    use crate::monitor::status::{Observability, Resolution};
    use crate::telemetry::{decode, encode, sample_frame_max, status_frame_max};

    /// A status of `N` joints with every field set, distinct per joint.
    fn status<const N: usize>() -> Status<N> {
        let mut s = Status::<N> {
            t_s: 12.345,
            samples: 70_000,
            ..Default::default()
        };
        for (j, js) in s.joints.iter_mut().enumerate() {
            let x = j as f32 + 0.25;
            *js = JointStatus {
                phi_deg: -x,
                rate_deg_s: 3.0 * x,
                coulomb_nm: 0.01 * x,
                coulomb_sd_nm: 0.002,
                viscous_nms: 1e-3 * x,
                viscous_sd_nms: 0.5,
                viscous: Observability::Estimated,
                friction_torque_nm: 0.02,
                latch: LatchState::Latched,
                margin_pct: (j != 1).then_some(150.0 + x),
                prediction: Prediction::Stall,
                confidence: 0.9,
                time_to_latch_s: (j == 1).then_some(0.75),
                faults: FaultFlags::default(),
                resolution: if j == 0 {
                    Resolution::Unresolved
                } else {
                    Resolution::Resolved
                },
            };
            js.faults.insert(Fault::SwitchChatter);
        }
        s
    }

    #[test]
    fn a_status_view_writes_the_bytes_of_the_status_it_views() {
        fn check<const N: usize>() {
            let s = status::<N>();
            let mut a = [0u8; 512];
            let mut b = [0u8; 512];
            let n = encode(&s, &mut a).expect("fits").len();
            assert!(n <= status_frame_max(N));
            assert_eq!(StatusView::of(&s).encode(&mut b), Ok(n));
            assert_eq!(a[..n], b[..n]);
            // Too small a buffer fails alike.
            let short = n - 1;
            assert_eq!(
                StatusView::of(&s).encode(&mut b[..short]),
                encode(&s, &mut a[..short]).map(|f| f.len())
            );
        }
        check::<1>();
        check::<2>();
        check::<3>();
        check::<4>();
    }

    /// The frame of a sample of `N` joints.
    fn frame<const N: usize>(k: u8) -> ([u8; 64], usize) {
        let s = Sample::<N>::new(
            0.01 * f32::from(k),
            core::array::from_fn(|j| {
                if j == 1 {
                    f32::NAN
                } else {
                    10.0 * j as f32 - 3.5
                }
            }),
            core::array::from_fn(|j| (j + usize::from(k)) % 2 == 0),
        );
        let mut buf = [0u8; 64];
        let n = encode(&s, &mut buf).expect("fits").len();
        assert!(n <= sample_frame_max(N));
        (buf, n)
    }

    /// Decodes `bytes` as a `Sample<N>` and as a counted sample of `N`
    /// joints: the same result, NaN readings compared bit for bit.
    fn same<const N: usize>(bytes: &[u8]) {
        let (mut a, mut b) = ([0u8; 64], [0u8; 64]);
        a[..bytes.len()].copy_from_slice(bytes);
        b[..bytes.len()].copy_from_slice(bytes);
        let generic = decode::<Sample<N>>(&mut a[..bytes.len()]);
        let counted = CountedSample::decode(&mut b[..bytes.len()], N);
        match (generic, counted) {
            (Ok(g), Ok(c)) => {
                assert_eq!(c.joints, N);
                assert_eq!(c.t_s.to_bits(), g.t_s.to_bits());
                for j in 0..N {
                    assert_eq!(c.phi_deg[j].to_bits(), g.phi_deg[j].to_bits());
                    assert_eq!(c.latch[j], g.latch[j]);
                }
                let back = c.to_sample::<N>().expect("N joints");
                assert_eq!(back.phi_deg.map(f32::to_bits), g.phi_deg.map(f32::to_bits));
                assert_eq!(back.latch, g.latch);
                assert_eq!(CountedSample::of(&g).map(|s| s.joints), Some(N));
            }
            (g, c) => assert_eq!(g.err(), c.err(), "{bytes:?}"),
        }
    }

    #[test]
    fn a_counted_sample_reads_the_frames_a_sample_reads() {
        for k in 0..4 {
            let (f2, n2) = frame::<2>(k);
            let (f3, n3) = frame::<3>(k);
            for bytes in [&f2[..n2], &f3[..n3]] {
                same::<1>(bytes);
                same::<2>(bytes);
                same::<3>(bytes);
            }
        }
        // Every frame with one byte changed: bad CRC, bad COBS, a switch
        // byte that is not a bool, a frame cut short.
        let (f, n) = frame::<3>(1);
        for i in 0..n {
            for v in [0u8, 1, 2, 0x80, 0xff] {
                let mut bad = f;
                bad[i] = v;
                same::<3>(&bad[..n]);
                same::<2>(&bad[..n]);
            }
            same::<3>(&f[..i]);
        }
    }

    /// The frame of a raw `payload` (postcard bytes and CRC as given).
    fn framed(payload: &[u8]) -> Vec<u8> {
        let mut out = vec![0u8; payload.len() + payload.len() / 254 + 2];
        let n = cobs::encode(payload, &mut out);
        out.truncate(n);
        out.push(0);
        out
    }

    #[test]
    fn a_counted_sample_reads_the_payloads_a_sample_reads() {
        // Payloads cut short, with bytes after the CRC, with a switch byte
        // of 2, and with the CRC of the bytes as they are (the reader must
        // then agree on the values, not only on the error).
        let (mut f, n) = frame::<3>(2);
        let len = cobs::decode_in_place(&mut f[..n]).expect("cobs");
        let good = f[..len].to_vec();
        for cut in 0..=good.len() {
            same::<3>(&framed(&good[..cut]));
            same::<2>(&framed(&good[..cut]));
        }
        let mut longer = good.clone();
        longer.extend_from_slice(&[7, 0, 9]);
        same::<3>(&framed(&longer));
        same::<2>(&framed(&longer));
        for body_len in [4 + 5 * 2, 4 + 5 * 3] {
            for switch in [0u8, 1, 2, 0xff] {
                let mut body = good[..body_len].to_vec();
                *body.last_mut().expect("a byte") = switch;
                let crc = CRC.checksum(&body).to_le_bytes();
                body.extend_from_slice(&crc);
                same::<3>(&framed(&body));
                same::<2>(&framed(&body));
            }
        }
    }

    #[test]
    fn a_counted_sample_is_only_the_sample_of_its_joint_count() {
        let (mut f, n) = frame::<2>(0);
        let s = CountedSample::decode(&mut f[..n], 2).expect("decodes");
        assert!(s.to_sample::<2>().is_some());
        assert!(s.to_sample::<3>().is_none());
        assert_eq!(
            CountedSample::decode(&mut frame::<2>(0).0[..n], MAX_JOINTS + 1),
            Err(TelemetryError::BadPayload)
        );
        let eight = CountedSample::of(&Sample::new(1.0, [2.0; MAX_JOINTS], [true; MAX_JOINTS]));
        assert_eq!(
            eight.and_then(|s| s.to_sample::<MAX_JOINTS>()),
            Some(Sample::new(1.0, [2.0; MAX_JOINTS], [true; MAX_JOINTS]))
        );
        assert!(CountedSample::of(&Sample::new(0.0, [0.0; 9], [false; 9])).is_none());
    }
}
