//! Mutated inputs are accepted or rejected with a located error, never a
//! panic.

use super::*;

/// A small deterministic generator (64-bit LCG) for the mutation test.
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 33) as usize) % n.max(1)
    }
}

/// `text` with a few characters deleted, inserted or replaced.
fn mutate(text: &str, rng: &mut Lcg) -> String {
    const ALPHABET: &[char] = &[
        '0', '1', '9', '.', ',', '-', '#', '=', '"', '[', ']', '{', '}', '\n', ' ', 'e', 'n', 'a',
        '_', '°',
    ];
    let mut chars: Vec<char> = text.chars().collect();
    for _ in 0..1 + rng.below(3) {
        let i = rng.below(chars.len() + 1);
        let c = ALPHABET[rng.below(ALPHABET.len())];
        match rng.below(3) {
            0 if i < chars.len() => {
                chars.remove(i);
            }
            1 if i < chars.len() => chars[i] = c,
            _ => chars.insert(i, c),
        }
    }
    chars.into_iter().collect()
}

#[test]
fn mutated_inputs_are_accepted_or_rejected_with_a_located_error_never_a_panic() {
    let mut rng = Lcg(2026);
    let t01 = t01_text();
    let mut rejected = (0, 0);
    for _ in 0..3000 {
        let text = mutate(GOOD, &mut rng);
        if let Err(e) = Run::parse(&text, "bad.csv") {
            rejected.0 += 1;
            assert!(e.to_string().starts_with("bad.csv:"), "{e}");
            assert!(e.line().is_some(), "{e}");
        }
        let text = mutate(&t01, &mut rng);
        if let Err(e) = Mechanism::from_toml_str(&text, "bad.toml") {
            rejected.1 += 1;
            assert!(e.to_string().starts_with("bad.toml"), "{e}");
            assert!(e.line().is_some() || e.key().is_some(), "{e}");
        }
    }
    // The mutations do break most files.
    assert!(rejected.0 > 1000 && rejected.1 > 1000, "{rejected:?}");
}
