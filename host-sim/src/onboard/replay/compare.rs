//! The check that two sides gave the same statuses: byte for byte, and on a
//! difference the first differing frame, joint and field.

use super::decode::{decode_statuses, frames};
use super::error::Mismatch;

/// Field name → value of a serialisable value, for the comparison.
fn fields<T: serde::Serialize>(value: &T) -> Vec<(String, serde_json::Value)> {
    match serde_json::to_value(value) {
        Ok(serde_json::Value::Object(m)) => m.into_iter().collect(),
        Ok(v) => vec![("value".into(), v)],
        Err(_) => Vec::new(),
    }
}

/// Compares the host's status frames with a target's, byte for byte; on a
/// difference, names the first differing frame, joint and field (decoded
/// with `joints`). Returns the number of frames when identical.
pub fn compare(host: &[u8], target: &[u8], joints: usize) -> Result<usize, Mismatch> {
    let (h, t): (Vec<&[u8]>, Vec<&[u8]>) = (frames(host).collect(), frames(target).collect());
    if host == target {
        return Ok(h.len());
    }
    let Some(i) = h.iter().zip(t.iter()).position(|(a, b)| a != b) else {
        return Err(Mismatch {
            frame: h.len().min(t.len()),
            joint: None,
            field: "number of frames".into(),
            host: h.len().to_string(),
            target: t.len().to_string(),
        });
    };
    let bytes = Mismatch {
        frame: i,
        joint: None,
        field: "frame bytes".into(),
        host: format!("{:02x?}", h[i]),
        target: format!("{:02x?}", t[i]),
    };
    let (Ok(a), Ok(b)) = (decode_statuses(h[i], joints), decode_statuses(t[i], joints)) else {
        return Err(bytes);
    };
    let (a, b) = (&a[0], &b[0]);
    let top = [
        ("t_s", bits(a.t_s), bits(b.t_s)),
        ("samples", a.samples.to_string(), b.samples.to_string()),
    ];
    for (field, x, y) in top {
        if x != y {
            return Err(Mismatch {
                frame: i,
                joint: None,
                field: field.into(),
                host: x,
                target: y,
            });
        }
    }
    for (j, (x, y)) in a.joints.iter().zip(b.joints.iter()).enumerate() {
        for ((name, u), (_, v)) in fields(x).into_iter().zip(fields(y)) {
            if u != v {
                return Err(Mismatch {
                    frame: i,
                    joint: Some(j + 1),
                    field: name,
                    host: u.to_string(),
                    target: v.to_string(),
                });
            }
        }
    }
    Err(bytes)
}

fn bits(x: f32) -> String {
    format!("{x:?} ({:#010x})", x.to_bits())
}
