//! `deploywatch margin`: the torque margins of every joint of a mechanism
//! (`docs/margin.md`, `physics.md` 9).
//!
//! For each joint it prints `T_D` (the spring torque at the stowed angle on
//! the unfolding branch), `T_R` (the friction: `--friction`, what `--from`
//! found added to the joint's `friction.coulomb_nm`, or that value alone),
//! the torque-form margin (seed 001 Eq. 7), `E_D`, `E_R = T_R · stroke` plus
//! the energy a viscous damping dissipates on the deployment, and the
//! energy-form margin (seed 000 Eq. 21), with the chosen standard's friction
//! factor applied, and pass/fail against its required minimum. A joint with
//! a physical latch (`[joint.latch]`) also counts the plunger's engagement
//! as a resistance, factored as [`LATCH_KIND`]: its entry torque in the
//! torque form, its engagement energy in the energy form, each printed on
//! a line of its own. `--json` writes the same table.
pub use super::margin_from::{read_found, resistances_with, FromError, Resistances};
use super::{check_output, CliError, Console};
use crate::analysis::design_margin::{
    joint_margin, Factors, JointMargin, LatchResistance, NameError, Resistance, Standard,
    LATCH_KIND,
};
use crate::analysis::effect_margin::{self, Counted, EffectWork};
use crate::model::effect::{Effect, EffectKind};
use crate::model::mechanism::Mechanism;
use crate::report::files::Outputs;
use clap::builder::PossibleValue;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Arguments of `deploywatch margin`.
#[derive(clap::Args, Debug)]
pub struct MarginArgs {
    /// Mechanism file (TOML, docs/spec/formats.md).
    #[arg(long, value_name = "M.toml")]
    pub mechanism: PathBuf,

    /// Friction (EFT) per joint [N·m], comma-separated, one value per joint
    /// (e.g. 0.54,0.472); default: each joint's friction.coulomb_nm.
    #[arg(
        long,
        value_name = "NM,NM,..",
        value_delimiter = ',',
        conflicts_with = "from"
    )]
    pub friction: Option<Vec<f64>>,

    /// What `identify` or `diagnose` found (their --json output): the EFT
    /// per joint [N·m] (identify), or the coulomb_friction [N·m] and
    /// viscous_damping [N·m·s/rad] per joint (diagnose), added to the
    /// mechanism's own friction.
    #[arg(long, value_name = "FILE.json")]
    pub from: Option<PathBuf>,

    /// Flight standard whose uncertainty factors and minimum margin apply.
    #[arg(long, value_enum, ignore_case = true, default_value_t = Standard::None)]
    pub standard: Standard,

    /// Override one uncertainty factor, KIND=VALUE (kinds: inertia, spring,
    /// friction, hysteresis, harness, adhesion, other); may be repeated.
    #[arg(long = "factor", value_name = "KIND=VALUE", value_parser = parse_factor)]
    pub factors: Vec<(Resistance, f64)>,

    /// Also write the margins as JSON here.
    #[arg(long, value_name = "OUT.json")]
    pub json: Option<PathBuf>,

    /// No chatter: the table, errors and warnings only; the JSON is
    /// written as usual.
    #[arg(long, short)]
    pub quiet: bool,

    /// The margin on orbit: the mechanism's `[rig]` taken out and the
    /// effects that exist only on the ground rig (`air_drag`, `rig_tilt`)
    /// left out of what `--from` found.
    #[arg(long)]
    pub flight: bool,

    /// Exit 1 when a joint fails either margin (after printing the table
    /// and writing the JSON); without it the exit code says only whether
    /// the margins could be computed.
    #[arg(long)]
    pub check: bool,
}

/// `--standard` takes the names of [`Standard::ALL`], each with its
/// reference as help, so `--help` lists them.
impl clap::ValueEnum for Standard {
    fn value_variants<'a>() -> &'a [Self] {
        &Standard::ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        let aliases: &[&str] = match self {
            Standard::None => &[],
            Standard::NasaStd5017 => &["nasa-std-5017b", "nasa"],
            Standard::EcssEST3301C => &["ecss"],
        };
        Some(
            PossibleValue::new(self.name())
                .help(self.reference())
                .aliases(aliases.iter().copied()),
        )
    }

    fn from_str(input: &str, _ignore_case: bool) -> Result<Self, String> {
        input.parse().map_err(|e: NameError| e.to_string())
    }
}

/// What is wrong with a `--factor KIND=VALUE`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FactorError {
    /// No `=`.
    #[error("`{text}`: expected KIND=VALUE, e.g. friction=2.5")]
    NotKeyValue {
        /// The whole text.
        text: String,
    },
    /// Not a kind of resistance.
    #[error(transparent)]
    Kind(#[from] NameError),
    /// A value that does not parse.
    #[error("`{value}` is not a number")]
    NotANumber {
        /// The value as written.
        value: String,
    },
    /// A value that is not a positive finite number.
    #[error("factor `{value}` must be a positive number")]
    NotPositive {
        /// The value as written.
        value: String,
    },
}

fn parse_factor(s: &str) -> Result<(Resistance, f64), FactorError> {
    let (k, v) = s.split_once('=').ok_or_else(|| FactorError::NotKeyValue {
        text: s.to_string(),
    })?;
    let kind: Resistance = k.parse()?;
    let value: f64 = v.trim().parse().map_err(|_| FactorError::NotANumber {
        value: v.to_string(),
    })?;
    if !(value.is_finite() && value > 0.0) {
        return Err(FactorError::NotPositive {
            value: v.to_string(),
        });
    }
    Ok((kind, value))
}

/// A margin [%] for the table: `inf` when there is no resistance.
fn pct(v: f64) -> String {
    if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.to_string()
    } else {
        format!("{v:.2}")
    }
}

fn verdict(m: &JointMargin) -> &'static str {
    match (m.torque_pass(), m.energy_pass()) {
        (true, true) => "pass",
        (false, true) => "FAIL (torque)",
        (true, false) => "FAIL (energy)",
        (false, false) => "FAIL",
    }
}

/// The resistances from `--friction`, or the mechanism's own friction.
fn given_resistances(args: &MarginArgs, mech: &Mechanism) -> Result<Resistances, CliError> {
    let n = mech.joint_count();
    let viscous_nms = mech.joints.iter().map(|j| j.friction.viscous_nms).collect();
    let Some(v) = &args.friction else {
        return Ok(Resistances {
            coulomb_nm: mech.joints.iter().map(|j| j.friction.coulomb_nm).collect(),
            viscous_nms,
            source: "the mechanism's friction".into(),
            ignored: Vec::new(),
            others: Vec::new(),
            found_on: Vec::new(),
        });
    };
    if v.len() != n {
        return Err(CliError::input(format!(
            "--friction has {} values but {} has {n} joints",
            v.len(),
            args.mechanism.display()
        )));
    }
    if let Some(bad) = v.iter().find(|x| !(x.is_finite() && **x >= 0.0)) {
        return Err(CliError::input(format!(
            "--friction: {bad} is not a friction torque (a number ≥ 0 N·m)"
        )));
    }
    Ok(Resistances {
        coulomb_nm: v.clone(),
        viscous_nms,
        source: "--friction".into(),
        ignored: Vec::new(),
        others: Vec::new(),
        found_on: Vec::new(),
    })
}

/// What was found, as effects on top of the mechanism (which already
/// holds its own friction): the differences of the friction and damping
/// lists, and every other effect.
fn found_effects(mech: &Mechanism, r: &Resistances) -> Vec<Effect> {
    let n = mech.joint_count();
    (0..n)
        .flat_map(|j| {
            let own = &mech.joints[j].friction;
            [
                Effect::joint(
                    EffectKind::CoulombFriction,
                    j + 1,
                    r.coulomb_nm[j] - own.coulomb_nm,
                ),
                Effect::joint(
                    EffectKind::ViscousDamping,
                    j + 1,
                    r.viscous_nms[j] - own.viscous_nms,
                ),
            ]
        })
        .chain(r.others.iter().copied())
        .collect()
}

/// What the simulated deployment gives the margins: each joint's viscous
/// energy `∫ f · φ̇² dt` [J] (rectangle rule on the sample grid, zero where
/// `f = 0`), and per effect of `r.others` its resisting work and its
/// generalised torque at the stowed state
/// ([`effect_margin::resisting_work`]). No simulation when nothing needs it.
fn simulated(mech: &Mechanism, r: &Resistances) -> Result<(Vec<f64>, EffectWork), CliError> {
    let n = mech.joint_count();
    let zero_others = vec![vec![0.0; n]; r.others.len()];
    let needed = r.viscous_nms.iter().any(|f| *f != 0.0)
        || r.others
            .iter()
            .any(|e| effect_margin::needs_simulation(e.kind));
    if !needed {
        let work = EffectWork {
            work_j: zero_others.clone(),
            stowed_torque_nm: zero_others,
        };
        return Ok((vec![0.0; n], work));
    }
    let traj = effect_margin::deployment(mech, &found_effects(mech, r))
        .map_err(|e| CliError::failed(format!("the deployment with what was found: {e}")))?;
    let dt = traj.t_s.windows(2).map(|w| w[1] - w[0]);
    let viscous = (0..n)
        .map(|j| {
            let rate = &traj.rate_deg_s[j];
            dt.clone()
                .zip(rate)
                .map(|(dt, w)| r.viscous_nms[j] * w.to_radians().powi(2) * dt)
                .sum()
        })
        .collect();
    Ok((
        viscous,
        effect_margin::resisting_work(mech, &r.others, &traj),
    ))
}

/// One row of the table.
#[derive(Clone, Debug)]
pub struct Row {
    /// 1-based joint.
    pub joint: usize,
    /// Stowed angle [deg].
    pub stowed_deg: f64,
    /// Viscous damping [N·m·s/rad].
    pub viscous_nms: f64,
    /// The energy the viscous damping dissipates on the deployment [J],
    /// included in `margin.resisting_energy_j`.
    pub viscous_energy_j: f64,
    /// The margins.
    pub margin: JointMargin,
    /// Each other effect found on this joint (or global) and how it is
    /// counted.
    pub counted: Vec<(Effect, Counted)>,
}

/// The margins of every joint with the resistances `r` and `factors`.
fn margins(
    mech: &Mechanism,
    path: &Path,
    r: &Resistances,
    standard: Standard,
    factors: &Factors,
) -> Result<Vec<Row>, CliError> {
    let (viscous, w) = simulated(mech, r)?;
    let mut rows = Vec::with_capacity(mech.joint_count());
    for (j, joint) in mech.joints.iter().enumerate() {
        let spring = joint.spring.to_spring().map_err(|e| {
            CliError::input(format!(
                "{}: joint {}: bad spring: {e}",
                path.display(),
                j + 1
            ))
        })?;
        let mut m = joint_margin(
            &spring,
            joint.stowed_deg.to_radians(),
            r.coulomb_nm[j],
            standard,
            Some(factors),
        );
        m.resisting_energy_j += viscous[j];
        let mut m = m.with_latch(latch_resistance(mech, j));
        let mut counted = Vec::new();
        for (i, e) in r.others.iter().enumerate() {
            let Some(c) =
                effect_margin::counted(mech, j, e, w.work_j[i][j], w.stowed_torque_nm[i][j])
            else {
                continue;
            };
            match c {
                Counted::Resistance {
                    kind,
                    torque_nm,
                    energy_j,
                } => m.add_resistance(kind, torque_nm, energy_j, factors),
                Counted::Driving { scale } => m.scale_driving(scale),
                Counted::Sensor => {}
            }
            counted.push((*e, c));
        }
        rows.push(Row {
            joint: j + 1,
            stowed_deg: joint.stowed_deg,
            viscous_nms: r.viscous_nms[j],
            viscous_energy_j: viscous[j],
            margin: m,
            counted,
        });
    }
    Ok(rows)
}

/// `--flight`: leaves out the effects that exist only on the ground rig
/// ([`effect_margin::rig_only`]), naming them in the source.
fn take_out_the_rig(r: &mut Resistances) {
    let (rig, flies): (Vec<Effect>, Vec<Effect>) = r
        .others
        .iter()
        .partition(|e| effect_margin::rig_only(e.kind));
    r.others = flies;
    let names: Vec<String> = rig.iter().map(|e| e.kind.to_string()).collect();
    r.source = if names.is_empty() {
        format!("{}; flight: the rig taken out", r.source)
    } else {
        format!(
            "{}; flight: the rig taken out, left out as rig-only: {}",
            r.source,
            names.join(", ")
        )
    };
}

/// The engagement of joint `j`'s physical latch (0-based) as a resistance,
/// from the core's law in `f64` (`physics.md` §10.3); zero for the ideal
/// latch.
pub fn latch_resistance(mech: &Mechanism, j: usize) -> LatchResistance {
    let (Some(spec), Some(joint)) = (mech.latch(j), mech.joints.get(j)) else {
        return LatchResistance::default();
    };
    let l = spec.to_core::<f64>(joint.stowed_deg, 1.0, 1.0);
    LatchResistance {
        entry_torque_nm: l.entry_torque(),
        engagement_energy_j: l.engagement_energy(),
    }
}

/// Runs `deploywatch margin`.
pub fn run(args: &MarginArgs) -> Result<(), CliError> {
    // The loader's errors name the file, the key and what was expected.
    let mech = Mechanism::load(&args.mechanism).map_err(|e| CliError::input(e.to_string()))?;
    let mech = if args.flight { mech.flight() } else { mech };
    let mut resist = match &args.from {
        Some(path) => read_found(path, &mech)
            .map_err(|e| CliError::input(format!("--from {}: {e}", path.display())))?,
        None => given_resistances(args, &mech)?,
    };
    if args.flight {
        take_out_the_rig(&mut resist);
    }
    if let Some(out) = &args.json {
        check_output("--json", out)?;
    }
    let console = Console::new(args.quiet);
    for w in crate::model::plausibility::warnings(&mech, &args.mechanism) {
        console.warn(w);
    }
    if !resist.found_on.is_empty() && !resist.found_on.contains(&mech.name) {
        console.warn(format_args!(
            "the friction in --from was found on {}, not on {}: it is applied as it is",
            resist.found_on.join(", "),
            mech.name
        ));
    }
    let mut factors = args.standard.factors();
    for (kind, value) in &args.factors {
        factors.set(*kind, *value);
    }
    let rows = margins(&mech, &args.mechanism, &resist, args.standard, &factors)?;
    super::print_out(format_args!(
        "{}",
        table(args, &mech, &resist, &factors, &rows)
    ));
    if let Some(out) = &args.json {
        let doc = to_json(args, &mech, &resist, &factors, &rows);
        let text =
            serde_json::to_string_pretty(&doc).map_err(|e| CliError::failed(e.to_string()))?;
        let mut outs = Outputs::new();
        outs.write(out, text + "\n")?;
        outs.commit()?;
        console.say(format_args!("json: {}", out.display()));
    }
    let failed: Vec<String> = rows
        .iter()
        .filter(|r| !(r.margin.torque_pass() && r.margin.energy_pass()))
        .map(|r| r.joint.to_string())
        .collect();
    if args.check && !failed.is_empty() {
        return Err(CliError::failed(format!(
            "margin --check: joint(s) {} of `{}` FAIL",
            failed.join(", "),
            mech.name
        )));
    }
    Ok(())
}

/// The header lines: mechanism, source of the resistances, standard.
fn table_header(args: &MarginArgs, mech: &Mechanism, r: &Resistances, factors: &Factors) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let custom = *factors != args.standard.factors();
    let _ = writeln!(
        s,
        "torque margins of `{}` ({})",
        mech.name,
        args.mechanism.display()
    );
    let _ = writeln!(s, "resistances from: {}", r.source);
    if !r.ignored.is_empty() {
        let _ = writeln!(
            s,
            "not a named effect, not in these margins: {}",
            r.ignored.join(", ")
        );
    }
    let _ = writeln!(
        s,
        "standard: {}{}",
        args.standard.reference(),
        if custom { " (factors overridden)" } else { "" }
    );
    if args.standard != Standard::None || custom {
        let list: Vec<String> = Resistance::ALL
            .iter()
            .map(|r| format!("{r} {}", factors.get(*r)))
            .collect();
        let _ = writeln!(s, "uncertainty factors: {}", list.join(", "));
        let _ = writeln!(
            s,
            "applied to the friction: {} ; to a latch's engagement ({}): {} ; required minimum margin: {:.0} %",
            factors.get(Resistance::Friction),
            LATCH_KIND,
            factors.get(LATCH_KIND),
            args.standard.required_margin() * 100.0
        );
        let _ = writeln!(
            s,
            "margins below: D / (FoS_friction · R + FoS_{LATCH_KIND} · R_latch) − 1"
        );
    } else {
        let _ = writeln!(
            s,
            "margins below: D / R − 1 (seed 001 Eq. 7, seed 000 Eq. 21); pass at ≥ 0 %"
        );
    }
    if mech.has_physical_latch() {
        let _ = writeln!(
            s,
            "R includes a physical latch's engagement (T_e in the torque form, E_eng in the energy form)"
        );
    }
    if !r.others.is_empty() {
        let _ = writeln!(
            s,
            "R includes every other effect found, each with its kind's factor (a line under its joint); a spring_softening scales D"
        );
    }
    if r.viscous_nms.iter().any(|f| *f != 0.0) {
        let _ = writeln!(
            s,
            "E_R includes E_visc, the energy the viscous damping dissipates on the simulated deployment"
        );
    }
    s
}

/// The table printed on the terminal.
fn table(
    args: &MarginArgs,
    mech: &Mechanism,
    r: &Resistances,
    factors: &Factors,
    rows: &[Row],
) -> String {
    use std::fmt::Write as _;
    let mut s = table_header(args, mech, r, factors);
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "{:>5} {:>10} {:>9} {:>9} {:>11} {:>9} {:>9} {:>9} {:>11}  result",
        "joint",
        "stowed_deg",
        "T_D_Nm",
        "T_R_Nm",
        "TM_torque_%",
        "E_D_J",
        "E_visc_J",
        "E_R_J",
        "TM_energy_%",
    );
    for row in rows {
        let m = &row.margin;
        let _ = writeln!(
            s,
            "{:>5} {:>10.2} {:>9.4} {:>9.4} {:>11} {:>9.4} {:>9.4} {:>9.4} {:>11}  {}",
            row.joint,
            row.stowed_deg,
            m.driving_torque_nm,
            m.resisting_torque_nm,
            pct(m.torque_margin_pct()),
            m.driving_energy_j,
            row.viscous_energy_j,
            m.resisting_energy_j,
            pct(m.energy_margin_pct()),
            verdict(m)
        );
        for (e, c) in &row.counted {
            let _ = writeln!(s, "{:>5} {}", "", counted_line(e, c, factors));
        }
        if m.latch != LatchResistance::default() {
            let _ = writeln!(
                s,
                "{:>5} latch engagement ({LATCH_KIND}, factor {}): T_e {:.4} N·m in the torque form, E_eng {:.4} J in the energy form",
                "",
                m.latch_factor,
                m.latch.entry_torque_nm,
                m.latch.engagement_energy_j,
            );
        }
    }
    s
}

/// How an effect found is counted, for the table: e.g. `harness_stiffness
/// 0.5 N·m/rad (harness, factor 3): 1.5708 N·m in the torque form, 1.2337 J
/// in the energy form`.
fn counted_line(e: &Effect, c: &Counted, factors: &Factors) -> String {
    let what = format!("{} {} {}", e.kind, e.value, e.kind.unit());
    match c {
        Counted::Resistance {
            kind,
            torque_nm,
            energy_j,
        } => format!(
            "{what} ({kind}, factor {}): {torque_nm:.4} N·m in the torque form, {energy_j:.4} J in the energy form",
            factors.get(*kind)
        ),
        Counted::Driving { scale } => {
            format!("{what}: the driving spring × {scale:.4} (T_D and E_D above)")
        }
        Counted::Sensor => format!("{what}: a sensor effect, no torque (0 in both forms)"),
    }
}

/// How an effect found is counted, for `--json`.
fn counted_json(e: &Effect, c: &Counted) -> Value {
    let (counts_as, torque, energy, scale) = match c {
        Counted::Resistance {
            kind,
            torque_nm,
            energy_j,
        } => (kind.name(), *torque_nm, *energy_j, 1.0),
        Counted::Driving { scale } => ("driving", 0.0, 0.0, *scale),
        Counted::Sensor => ("sensor", 0.0, 0.0, 1.0),
    };
    json!({
        "effect": e.kind.name(),
        "value": e.value,
        "counts_as": counts_as,
        "torque_nm": torque,
        "energy_j": energy,
        "driving_scale": scale,
    })
}

/// The margins as JSON (`--json`); an infinite margin (no resistance) is
/// `null`.
fn to_json(
    args: &MarginArgs,
    mech: &Mechanism,
    r: &Resistances,
    factors: &Factors,
    rows: &[Row],
) -> Value {
    let finite = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
    json!({
        "mechanism": mech.name,
        "mechanism_file": args.mechanism.display().to_string(),
        "resistances_from": r.source,
        "not_included": r.ignored,
        "standard": args.standard.name(),
        "factors": Resistance::ALL
            .iter()
            .map(|k| (k.name().to_string(), json!(factors.get(*k))))
            .collect::<serde_json::Map<_, _>>(),
        "required_margin_pct": args.standard.required_margin() * 100.0,
        "joints": rows.iter().map(|row| {
            let m = &row.margin;
            json!({
                "joint": row.joint,
                "stowed_deg": row.stowed_deg,
                "coulomb_nm": m.resisting_torque_nm,
                "viscous_nms": row.viscous_nms,
                "driving_torque_nm": m.driving_torque_nm,
                "torque_margin_pct": finite(m.torque_margin_pct()),
                "driving_energy_j": m.driving_energy_j,
                "viscous_energy_j": row.viscous_energy_j,
                "resisting_energy_j": m.resisting_energy_j,
                "latch_entry_torque_nm": m.latch.entry_torque_nm,
                "latch_engagement_energy_j": m.latch.engagement_energy_j,
                "energy_margin_pct": finite(m.energy_margin_pct()),
                "counted": row.counted.iter().map(|(e, c)| counted_json(e, c)).collect::<Vec<_>>(),
                "pass": m.torque_pass() && m.energy_pass(),
            })
        }).collect::<Vec<_>>(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::design_margin::Factors;

    #[test]
    fn factor_arguments_parse() {
        assert_eq!(
            parse_factor("friction=2.5").unwrap(),
            (Resistance::Friction, 2.5)
        );
        assert_eq!(
            parse_factor("Harness = 3").unwrap(),
            (Resistance::Harness, 3.0)
        );
        assert!(parse_factor("friction").is_err());
        assert!(parse_factor("friction=-1").is_err());
        assert!(parse_factor("glue=2").is_err());
        let std = |s: &str| <Standard as clap::ValueEnum>::from_str(s, true);
        assert_eq!(std("ECSS-E-ST-33-01C").unwrap(), Standard::EcssEST3301C);
        assert!(std("mil-std").is_err());
    }

    #[test]
    fn infinite_margins_print_as_inf() {
        assert_eq!(pct(f64::INFINITY), "inf");
        assert_eq!(pct(12.345), "12.35");
    }

    fn args(file: &str, friction: Option<Vec<f64>>) -> MarginArgs {
        MarginArgs {
            mechanism: PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("../data/mechanisms")
                .join(file),
            friction,
            from: None,
            standard: Standard::EcssEST3301C,
            factors: vec![(Resistance::Friction, 2.5)],
            json: None,
            quiet: true,
            check: false,
            flight: false,
        }
    }

    #[test]
    fn runs_on_the_bundled_mechanisms_and_rejects_bad_input() {
        run(&args("seed000_case1.toml", Some(vec![0.54, 0.472]))).unwrap();
        run(&args("seed001_T02.toml", None)).unwrap();
        let e = run(&args("seed000_case1.toml", Some(vec![0.54]))).unwrap_err();
        assert_eq!(e.code, 2);
        assert!(e.message.contains("2 joints"), "{}", e.message);
        let e = run(&args("seed000_case1.toml", Some(vec![0.54, f64::NAN]))).unwrap_err();
        assert_eq!(e.code, 2);
        let e = run(&args("no_such_file.toml", None)).unwrap_err();
        assert_eq!(e.code, 2);
        assert!(e.message.contains("no_such_file"), "{}", e.message);
    }

    #[test]
    fn unused_factors_is_unity() {
        // `Factors` is plain data: overriding one kind leaves the others.
        let mut f = Standard::NasaStd5017.factors();
        f.set(Resistance::Friction, 2.0);
        assert_eq!(f.spring, 1.5);
        assert_ne!(f, Factors::UNITY);
    }
}
