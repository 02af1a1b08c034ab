//! The replay's sample and status frames for a joint count known at run
//! time: read and written by one copy of the code for every joint count
//! (the firmware links the monitors of 2 and 3 joints, and its flash is
//! short), with the bytes of [`Sample<N>`] and [`Status<N>`] on the wire.
//!
//! Both are read and written without serde, field by field as postcard
//! encodes them (`crate::telemetry`'s frame: postcard, CRC-32C, COBS):
//! postcard writes a struct as its fields in order and an array
//! (`crate::monitor::serde_array`) as its elements, neither with a length.
//! A sample's payload is fixed-size — the time and `n` angles as `f32`
//! little-endian, then `n` switches as one byte each (0 or 1), then the
//! CRC-32C of those bytes — and [`CountedSample::decode`] reads exactly
//! the frames that [`telemetry::decode`](super::decode) reads as a
//! `Sample<n>`, to the same values, and fails on the others with the same
//! error. [`StatusView::encode`] writes the bytes
//! [`telemetry::encode`](super::encode) writes for the `Status<n>` it
//! views. The tests compare each with postcard's (every one-byte
//! corruption of a sample frame; statuses with every variant, flag width
//! and option). postcard's generic reader and writer, compiled for them,
//! took about 1.7 KiB more of the firmware's flash (`docs/performance.md`).

use super::config::FIRMWARE_MAX_JOINTS;
use super::{TelemetryError, CRC};
use crate::monitor::estimator::{Sample, Status};
use crate::monitor::status::JointStatus;

/// A [`Sample`] of `joints` joints, at most [`FIRMWARE_MAX_JOINTS`], the
/// count known at run time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CountedSample {
    /// Time stamp [s].
    pub t_s: f32,
    /// Encoder angle of each joint [deg], the first `joints` in use (the
    /// others 0).
    pub phi_deg: [f32; FIRMWARE_MAX_JOINTS],
    /// Latch switch of each joint (true = closed), the first `joints` in
    /// use (the others open).
    pub latch: [bool; FIRMWARE_MAX_JOINTS],
    /// Joints in use.
    pub joints: usize,
}

impl CountedSample {
    /// `sample` as a counted sample; `None` when it has more than
    /// [`FIRMWARE_MAX_JOINTS`] joints.
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
    /// [`FIRMWARE_MAX_JOINTS`] is [`TelemetryError::BadPayload`].
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
    /// switch open; `None` over [`FIRMWARE_MAX_JOINTS`].
    fn empty(joints: usize) -> Option<Self> {
        (joints <= FIRMWARE_MAX_JOINTS).then_some(CountedSample {
            t_s: 0.0,
            phi_deg: [0.0; FIRMWARE_MAX_JOINTS],
            latch: [false; FIRMWARE_MAX_JOINTS],
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

/// A [`Status`] of any joint count, borrowed, written as the frame of the
/// `Status<N>` it views.
#[derive(Clone, Copy, Debug)]
pub struct StatusView<'a> {
    /// Time stamp of the last sample used [s].
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

    /// Writes the status as one frame into `buf` and returns the frame's
    /// length: the bytes, and the error for a `buf` too short, of
    /// [`telemetry::encode`](super::encode) of the `Status<N>` it views.
    /// Written field by field (postcard's encoding of each, its CRC
    /// flavor and its COBS flavor step for step, [`FrameWriter`]), not
    /// through serde (the module's header).
    #[inline(never)]
    pub fn encode(&self, buf: &mut [u8]) -> super::Result<usize> {
        let mut w = FrameWriter::new(buf)?;
        w.f32(self.t_s)?;
        w.varint(self.samples)?;
        for j in self.joints {
            for v in [
                j.phi_deg,
                j.rate_deg_s,
                j.coulomb_nm,
                j.coulomb_sd_nm,
                j.viscous_nms,
                j.viscous_sd_nms,
            ] {
                w.f32(v)?;
            }
            w.varint(j.viscous as u32)?;
            w.f32(j.friction_torque_nm)?;
            w.varint(j.latch as u32)?;
            w.option(j.margin_pct)?;
            w.varint(j.prediction as u32)?;
            w.f32(j.confidence)?;
            w.option(j.time_to_latch_s)?;
            w.varint(u32::from(j.faults.0))?;
        }
        w.finish()
    }
}

/// Writes a frame as [`telemetry::encode`](super::encode) does: each
/// payload byte into the CRC-32C and, COBS-encoded, into the output (as
/// postcard's `CrcModifier` over its `Cobs` flavor over a slice: a
/// placeholder code byte first, the cobs crate's encoder state, the CRC
/// little-endian after the payload, then the code fixed and `0x00`).
/// postcard writes an `f32` as its 4 bytes little-endian, an unsigned
/// integer and an enum's variant index as a varint, an `Option` as a tag
/// byte (0 or 1) and its value.
struct FrameWriter<'b> {
    out: &'b mut [u8],
    len: usize,
    cobs: cobs::EncoderState,
    crc: crc::Digest<'static, u32>,
}

impl<'b> FrameWriter<'b> {
    /// A frame into `out`, its first code byte reserved.
    fn new(out: &'b mut [u8]) -> super::Result<Self> {
        let mut w = FrameWriter {
            out,
            len: 0,
            cobs: cobs::EncoderState::default(),
            crc: CRC.digest(),
        };
        w.put(0)?;
        Ok(w)
    }

    /// `b` at the end of the output.
    fn put(&mut self, b: u8) -> super::Result<()> {
        *self
            .out
            .get_mut(self.len)
            .ok_or(TelemetryError::BufferTooSmall)? = b;
        self.len += 1;
        Ok(())
    }

    /// `b` at `idx` of the output (a COBS code byte written back).
    fn set(&mut self, idx: usize, b: u8) -> super::Result<()> {
        *self
            .out
            .get_mut(idx)
            .ok_or(TelemetryError::BufferTooSmall)? = b;
        Ok(())
    }

    /// One byte COBS-encoded into the output.
    fn encoded(&mut self, b: u8) -> super::Result<()> {
        match self.cobs.push(b) {
            cobs::PushResult::AddSingle(n) => self.put(n),
            cobs::PushResult::ModifyFromStartAndSkip((idx, code)) => {
                self.set(idx, code)?;
                self.put(0)
            }
            cobs::PushResult::ModifyFromStartAndPushAndSkip((idx, code, n)) => {
                self.set(idx, code)?;
                self.put(n)?;
                self.put(0)
            }
        }
    }

    /// Payload bytes.
    fn bytes(&mut self, bytes: &[u8]) -> super::Result<()> {
        for b in bytes {
            self.crc.update(core::slice::from_ref(b));
            self.encoded(*b)?;
        }
        Ok(())
    }

    /// An `f32`: its bytes little-endian.
    fn f32(&mut self, v: f32) -> super::Result<()> {
        self.bytes(&v.to_le_bytes())
    }

    /// An unsigned integer (or an enum's variant index): 7 bits a byte,
    /// least significant first, the top bit set on every byte but the
    /// last.
    fn varint(&mut self, mut v: u32) -> super::Result<()> {
        loop {
            let low = (v & 0x7f) as u8;
            v >>= 7;
            if v == 0 {
                return self.bytes(&[low]);
            }
            self.bytes(&[low | 0x80])?;
        }
    }

    /// An `Option<f32>`: 0, or 1 and the value.
    fn option(&mut self, v: Option<f32>) -> super::Result<()> {
        match v {
            None => self.bytes(&[0]),
            Some(x) => {
                self.bytes(&[1])?;
                self.f32(x)
            }
        }
    }

    /// The CRC, the last code byte and the terminating `0x00`; the
    /// frame's length.
    fn finish(mut self) -> super::Result<usize> {
        let crc = core::mem::replace(&mut self.crc, CRC.digest()).finalize();
        for b in crc.to_le_bytes() {
            self.encoded(b)?;
        }
        let (idx, code) = core::mem::take(&mut self.cobs).finalize();
        self.set(idx, code)?;
        self.put(0)?;
        Ok(self.len)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::monitor::faults::FaultFlags;
    use crate::monitor::latch::LatchState;
    use crate::monitor::predictor::Prediction;
    use crate::monitor::status::Observability;
    use crate::telemetry::{decode, encode, sample_frame_max, status_frame_max};

    /// A status of `N` joints with every field set, distinct per joint;
    /// `k` picks the variants, the flags, the options and the sample
    /// count (varints of 1 to 5 bytes).
    fn status<const N: usize>(k: usize) -> Status<N> {
        const FLAGS: [u16; 6] = [0, 1, 0x7f, 0x80, 0x3fff, 0xffff];
        const SAMPLES: [u32; 5] = [0, 127, 128, 70_000, u32::MAX];
        let mut s = Status::<N> {
            t_s: 12.345 + k as f32,
            samples: SAMPLES[k % SAMPLES.len()],
            ..Default::default()
        };
        for (j, js) in s.joints.iter_mut().enumerate() {
            let x = j as f32 + 0.25;
            let v = j + k;
            *js = JointStatus {
                phi_deg: -x,
                rate_deg_s: 3.0 * x,
                coulomb_nm: 0.01 * x,
                coulomb_sd_nm: 0.002,
                viscous_nms: 1e-3 * x,
                viscous_sd_nms: 0.5,
                viscous: Observability::ALL[v % Observability::ALL.len()],
                friction_torque_nm: 0.02,
                latch: LatchState::ALL[v % LatchState::ALL.len()],
                margin_pct: (v % 2 == 0).then_some(150.0 + x),
                prediction: Prediction::ALL[v % Prediction::ALL.len()],
                confidence: 0.9,
                time_to_latch_s: (v % 3 == 1).then_some(0.75),
                faults: FaultFlags(FLAGS[v % FLAGS.len()]),
            };
        }
        s
    }

    #[test]
    fn a_status_view_writes_the_bytes_of_the_status_it_views() {
        fn check<const N: usize>(k: usize) {
            let s = status::<N>(k);
            let mut a = [0u8; 512];
            let mut b = [0u8; 512];
            let n = encode(&s, &mut a).expect("fits").len();
            assert!(n <= status_frame_max(N));
            assert_eq!(StatusView::of(&s).encode(&mut b), Ok(n));
            assert_eq!(a[..n], b[..n]);
            // A buffer of any length up to the frame's: the same error.
            for len in 0..n {
                assert_eq!(
                    StatusView::of(&s).encode(&mut b[..len]),
                    encode(&s, &mut a[..len]).map(|f| f.len()),
                    "{len} bytes"
                );
            }
        }
        for k in 0..40 {
            check::<1>(k);
            check::<2>(k);
            check::<3>(k);
            check::<4>(k);
        }
        // Zero bytes elsewhere in the payload (other COBS codes).
        let mut s = status::<4>(0);
        for (j, js) in s.joints.iter_mut().enumerate() {
            js.phi_deg = f32::from_bits(0x0001_0203 + 0x0404_0404 * j as u32);
        }
        let mut a = [0u8; 512];
        let mut b = [0u8; 512];
        let n = encode(&s, &mut a).expect("fits").len();
        assert_eq!(StatusView::of(&s).encode(&mut b), Ok(n));
        assert_eq!(a[..n], b[..n]);
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
            CountedSample::decode(&mut frame::<2>(0).0[..n], FIRMWARE_MAX_JOINTS + 1),
            Err(TelemetryError::BadPayload)
        );
        assert!(CountedSample::of(&Sample::new(0.0, [0.0; 4], [false; 4])).is_none());
    }
}
