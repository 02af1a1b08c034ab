//! A measured or simulated run: the run CSV of `docs/spec/formats.md`.

/// One run: time stamps, joint angles and latch switches, with metadata.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Run {
    /// `# key = "value"` lines before the header, in file order (values decoded).
    pub metadata: Vec<(String, String)>,
    /// `t_s` [s], strictly increasing.
    pub t_s: Vec<f64>,
    /// `phi<j>_deg`: `phi_deg[j][i]` is joint j+1 at sample i [deg].
    pub phi_deg: Vec<Vec<f64>>,
    /// `latch<j>`: `latch[j][i]` is joint j+1's switch at sample i.
    pub latch: Vec<Vec<bool>>,
}

impl Run {
    /// Number of joints.
    pub fn joints(&self) -> usize {
        self.phi_deg.len()
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// True when the run has no samples.
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// A metadata value.
    pub fn meta(&self, key: &str) -> Option<&str> {
        self.metadata
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// Sets (or replaces) a metadata value.
    pub fn set_meta(&mut self, key: &str, value: &str) {
        match self.metadata.iter_mut().find(|(k, _)| k == key) {
            Some(kv) => kv.1 = value.to_string(),
            None => self.metadata.push((key.to_string(), value.to_string())),
        }
    }

    /// The `mechanism` metadata: the name of the mechanism this run belongs to.
    pub fn mechanism(&self) -> Option<&str> {
        self.meta("mechanism")
    }
}
