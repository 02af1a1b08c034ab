//! The sensor faults: each kind with its parameters, the sensor it acts on,
//! and the names of the kinds.

/// Longest switch bounce the chatter fault models \[s\] (a switch bounces up
/// to 20 ms, `docs/robustness.md`).
pub const MAX_BOUNCE_S: f64 = 0.02;

/// Time slack when comparing a sample time with a window edge \[s\]: sample
/// times are written to 1 µs.
pub(super) const TIME_EPS_S: f64 = 1e-9;

/// What a dropped encoder reading becomes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DropoutMode {
    /// The driver repeats its last good reading (a frozen bus or FIFO).
    Stale,
    /// The reading is missing: `NaN`.
    Missing,
}

impl DropoutMode {
    /// The name used in the CLI syntax.
    pub fn name(self) -> &'static str {
        match self {
            DropoutMode::Stale => "stale",
            DropoutMode::Missing => "missing",
        }
    }
}

/// The sensor of a joint a fault acts on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FaultTarget {
    /// The encoder of joint `j` (1-based).
    Encoder(usize),
    /// The latch switch of joint `j` (1-based).
    Switch(usize),
    /// The time stamps (every joint).
    Clock,
}

/// One sensor fault. Joints are 1-based, times in seconds from the release,
/// angles in degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SensorFault {
    /// `dropout:joint=J:start=S:duration=D[:mode=stale|missing]` (default
    /// `missing`): the encoder gives no fresh reading in `[S, S + D)`.
    Dropout {
        /// Joint (1-based).
        joint: usize,
        /// Start of the dropout \[s\].
        start_s: f64,
        /// Its length \[s\].
        duration_s: f64,
        /// Stale or missing readings.
        mode: DropoutMode,
    },
    /// `spike:joint=J:t=T:magnitude=M[:samples=K]` (default 1 sample): `K`
    /// readings from the first sample at or after `T` are off by `M`.
    Spike {
        /// Joint (1-based).
        joint: usize,
        /// Time of the spike \[s\].
        t_s: f64,
        /// Added to the reading \[deg\].
        magnitude_deg: f64,
        /// Consecutive samples affected (at least 1).
        samples: usize,
    },
    /// `stuck:joint=J:start=S[:value=V]`: the encoder reads `V` from `S` to
    /// the end of the run (its last reading before `S` when no `V`).
    StuckAt {
        /// Joint (1-based).
        joint: usize,
        /// When it sticks \[s\].
        start_s: f64,
        /// The value it sticks at \[deg\]; `None`: the last reading before.
        value_deg: Option<f64>,
    },
    /// `parity:joint=J:rate=R[:bits=B]` (default 1 bit): a fraction `R` of
    /// the encoder's answer words get `B` bit flips.
    ParityError {
        /// Joint (1-based).
        joint: usize,
        /// Probability that a sample's word is corrupted, in `[0, 1]`.
        rate: f64,
        /// Bits flipped in a corrupted word, 1 to 4: odd numbers fail the
        /// parity check, even numbers pass it.
        bits: u32,
    },
    /// `chatter:joint=J:bounce=B`: the switch bounces for `B` seconds
    /// (at most [`MAX_BOUNCE_S`]) after each closing.
    SwitchChatter {
        /// Joint (1-based).
        joint: usize,
        /// Bounce time \[s\].
        bounce_s: f64,
    },
    /// `switch_stuck:joint=J:state=open|closed`: the switch reads `state`
    /// for the whole run.
    SwitchStuck {
        /// Joint (1-based).
        joint: usize,
        /// True: stuck closed; false: stuck open.
        closed: bool,
    },
    /// `jitter:sigma=S`: time-stamp jitter of σ = `S` seconds.
    TimeJitter {
        /// Standard deviation \[s\].
        sigma_s: f64,
    },
    /// `gap:start=S:duration=D`: no sample in `[S, S + D)`.
    TimeGap {
        /// Start of the gap \[s\].
        start_s: f64,
        /// Its length \[s\].
        duration_s: f64,
    },
}

/// The kinds of fault, as named in the CLI syntax.
pub const KINDS: [&str; 8] = [
    "dropout",
    "spike",
    "stuck",
    "parity",
    "chatter",
    "switch_stuck",
    "jitter",
    "gap",
];

impl SensorFault {
    /// The kind's name in the CLI syntax (one of [`KINDS`]).
    pub fn kind(&self) -> &'static str {
        match self {
            SensorFault::Dropout { .. } => "dropout",
            SensorFault::Spike { .. } => "spike",
            SensorFault::StuckAt { .. } => "stuck",
            SensorFault::ParityError { .. } => "parity",
            SensorFault::SwitchChatter { .. } => "chatter",
            SensorFault::SwitchStuck { .. } => "switch_stuck",
            SensorFault::TimeJitter { .. } => "jitter",
            SensorFault::TimeGap { .. } => "gap",
        }
    }

    /// The sensor the fault acts on.
    pub fn target(&self) -> FaultTarget {
        match *self {
            SensorFault::Dropout { joint, .. }
            | SensorFault::Spike { joint, .. }
            | SensorFault::StuckAt { joint, .. }
            | SensorFault::ParityError { joint, .. } => FaultTarget::Encoder(joint),
            SensorFault::SwitchChatter { joint, .. } | SensorFault::SwitchStuck { joint, .. } => {
                FaultTarget::Switch(joint)
            }
            SensorFault::TimeJitter { .. } | SensorFault::TimeGap { .. } => FaultTarget::Clock,
        }
    }

    /// The joint the fault acts on (1-based), `None` for clock faults.
    pub fn joint(&self) -> Option<usize> {
        match self.target() {
            FaultTarget::Encoder(j) | FaultTarget::Switch(j) => Some(j),
            FaultTarget::Clock => None,
        }
    }
}
