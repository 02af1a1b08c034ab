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
//! as a resistance, factored as [`crate::analysis::design_margin::LATCH_KIND`]: its entry torque in the
//! torque form, its engagement energy in the energy form, each printed on
//! a line of its own. `--json` writes the same table. The margins are
//! computed by [`crate::analysis::joint_margins`], the table written by
//! [`crate::report::margin`].
use super::{check_outputs, CliError, Console, Output};
use crate::analysis::design_margin::{DataSource, Factors, NameError, Resistance, Standard};
use crate::analysis::dynamic_margin::DynamicMargins;
use crate::analysis::joint_margins::{margins, MarginsError, Row};
use crate::analysis::nominal_deployment::NominalDeployment;
use crate::analysis::resistances::{read_found, Resistances};
use crate::analysis::stroke_margin::Allowance;
use crate::model::mechanism::Mechanism;
use crate::report::files::Outputs;
use crate::report::margin::{nominal_line, table, to_json, MarginReport};
use crate::report::margin_plot::plot_margins;
use crate::report::margin_standards::side_by_side;
use clap::builder::PossibleValue;
use std::path::PathBuf;

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
        allow_hyphen_values = true,
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

    /// Where the resistances' values come from (the standard's row of
    /// factors): analysis, test, or acceptance-extremes.
    #[arg(long, value_name = "SOURCE", default_value = "analysis", value_parser = parse_source)]
    pub data_source: DataSource,

    /// Override one uncertainty factor, KIND=VALUE (kinds: inertia, spring,
    /// friction, hysteresis, harness, adhesion, other); may be repeated.
    #[arg(long = "factor", value_name = "KIND=VALUE", value_parser = parse_factor)]
    pub factors: Vec<(Resistance, f64)>,

    /// The driving springs' torque tolerance [%]: the minimum spring is
    /// this much below the file's nominal, at every joint (a joint whose
    /// file declares a larger `spring_tolerance_pct` keeps its own).
    #[arg(long, value_name = "PCT", default_value_t = 0.0, value_parser = parse_pct)]
    pub spring_tolerance: f64,

    /// The loss of the driving springs' torque at end of life [%]
    /// (relaxation, creep; the file does not give it).
    #[arg(long, value_name = "PCT", default_value_t = 0.0, value_parser = parse_pct)]
    pub end_of_life: f64,

    /// The required time, in s, to complete each joint's stroke from rest:
    /// the dynamic margin's acceleration α = 2 S / T² (constant
    /// acceleration over the stroke S); without it the dynamic margin is
    /// not computed.
    #[arg(long, value_name = "T", value_parser = parse_time)]
    pub deploy_time: Option<f64>,

    /// Also write the margins as JSON here.
    #[arg(long, value_name = "OUT.json")]
    pub json: Option<PathBuf>,

    /// Also draw the static margin along the stroke, one panel per joint,
    /// the required minimum and the worst position marked, as a PNG here.
    #[arg(long, value_name = "FILE.png")]
    pub plot: Option<PathBuf>,

    /// No chatter: the table, errors and warnings only; the JSON is
    /// written as usual.
    #[arg(long, short)]
    pub quiet: bool,

    /// The margin on orbit: the mechanism's `[rig]` taken out and the
    /// effects that exist only on the ground rig (`air_drag`, `rig_tilt`)
    /// left out of what `--from` found.
    #[arg(long)]
    pub flight: bool,

    /// Print the margins under every standard side by side (torque form
    /// at the stowed angle, energy form, worst along the stroke) instead
    /// of one standard's table, each with its own factors (no --factor).
    #[arg(long, conflicts_with_all = ["json", "plot", "check", "deploy_time", "standard", "factors"])]
    pub all_standards: bool,

    /// Exit 1 when a joint fails either margin or is not held by its latch
    /// at the end of the nominal deployment (after printing the table and
    /// writing the JSON); without it the exit code says only whether the
    /// margins could be computed.
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
            Standard::AiaaS114 => &["aiaa"],
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

/// A [`DataSource`] by its name.
fn parse_source(s: &str) -> Result<DataSource, String> {
    DataSource::ALL
        .into_iter()
        .find(|d| d.name().eq_ignore_ascii_case(s.trim()))
        .ok_or_else(|| format!("`{s}`: expected analysis, test or acceptance-extremes"))
}

/// A time > 0 \[s\].
fn parse_time(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("`{s}`: expected a time in s greater than 0")),
    }
}

/// A percentage in `[0, 100)`.
fn parse_pct(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if (0.0..100.0).contains(&v) => Ok(v),
        _ => Err(format!("`{s}`: expected a percentage from 0 to below 100")),
    }
}

/// The resistances from `--friction`, or the mechanism's own friction.
fn given_resistances(args: &MarginArgs, mech: &Mechanism) -> Result<Resistances, CliError> {
    let n = mech.joint_count();
    let own = Resistances::of_mechanism(mech, "the mechanism's friction".into());
    let Some(v) = &args.friction else {
        return Ok(own);
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
        source: "--friction".into(),
        ..own
    })
}

/// The factors of `standard` (its row for `--data-source`, with the
/// `--factor` overrides) and every joint's margins with them.
fn rows_for(
    args: &MarginArgs,
    mech: &Mechanism,
    resist: &Resistances,
    standard: Standard,
    allowance: &Allowance,
) -> Result<(Factors, Vec<Row>), CliError> {
    let mut factors = standard.factors_for(args.data_source);
    for (i, (kind, value)) in args.factors.iter().enumerate() {
        if let Some((_, first)) = args.factors[..i].iter().find(|(k, _)| k == kind) {
            return Err(CliError::input(format!("--factor {kind}={value}: the factor {kind} is given twice ({kind}={first} before); expected each kind once")));
        }
        factors.set(*kind, *value);
    }
    let rows = margins(mech, resist, standard, &factors, allowance).map_err(|e| match e {
        MarginsError::Spring { .. } => {
            CliError::input(format!("{}: {e}", args.mechanism.display()))
        }
        other => CliError::failed(other.to_string()),
    })?;
    Ok((factors, rows))
}

/// `--all-standards`: the margins under every standard side by side.
fn print_all_standards(
    args: &MarginArgs,
    mech: &Mechanism,
    resist: &Resistances,
    allowance: &Allowance,
) -> Result<(), CliError> {
    let by_standard = Standard::ALL
        .into_iter()
        .map(|std| Ok((std, rows_for(args, mech, resist, std, allowance)?.1)))
        .collect::<Result<Vec<_>, CliError>>()?;
    let title = format!(
        "margins of `{}` ({}) under each standard; resistances from: {}",
        mech.name,
        args.mechanism.display(),
        resist.source
    );
    super::print_out(format_args!(
        "{}",
        side_by_side(&title, &by_standard, args.data_source)
    ));
    // The nominal deployment does not depend on the standard: once, below.
    let nominal = NominalDeployment::of(mech, resist).map_err(|e| e.to_string());
    super::print_out(format_args!("{}\n", nominal_line(&nominal)));
    Ok(())
}

/// Writes `--json` and `--plot`, all or none ([`Outputs`]).
fn write_outputs(
    args: &MarginArgs,
    report: &MarginReport,
    console: &Console,
) -> Result<(), CliError> {
    let mut outs = Outputs::new();
    if let Some(out) = &args.json {
        let doc = to_json(report);
        let text =
            serde_json::to_string_pretty(&doc).map_err(|e| CliError::failed(e.to_string()))?;
        outs.write(out, text + "\n")?;
    }
    if let Some(png) = &args.plot {
        plot_margins(
            &outs.path(png)?,
            &report.mech.name,
            report.standard.name(),
            report.rows,
        )
        .map_err(|e| CliError::failed(e.to_string()))?;
    }
    outs.commit()?;
    if let Some(out) = &args.json {
        console.say(format_args!("json: {}", out.display()));
    }
    if let Some(png) = &args.plot {
        console.say(format_args!("plot: {}", png.display()));
    }
    Ok(())
}

/// The joints (1-based, as text) that fail any margin: either form, along
/// the stroke, latching, or dynamic.
fn failed_joints(rows: &[Row], dynamic: &DynamicMargins) -> Vec<String> {
    rows.iter()
        .enumerate()
        .filter(|(i, r)| {
            !(r.margin.torque_pass()
                && r.margin.energy_pass()
                && r.stroke.pass()
                && r.margin.latching_pass()
                && dynamic.pass(*i))
        })
        .map(|(_, r)| r.joint.to_string())
        .collect()
}

/// After the table: warns of a joint that passes every margin and is not
/// held at the end of the nominal deployment, and fails `--check` on a
/// joint that fails a margin or is not held.
fn check_nominal(
    args: &MarginArgs,
    mech: &Mechanism,
    rows: &[Row],
    dynamic: &DynamicMargins,
    nominal: &Result<NominalDeployment, String>,
    console: &Console,
) -> Result<(), CliError> {
    let failed = failed_joints(rows, dynamic);
    let short = nominal.as_ref().map(|d| d.not_held()).unwrap_or_default();
    let passed_short: Vec<String> = short
        .iter()
        .filter(|j| !failed.contains(&j.to_string()))
        .map(|j| j.to_string())
        .collect();
    if !passed_short.is_empty() {
        console.warn(format_args!(
            "joint(s) {} of `{}` pass every margin but are not held by their latch at the end of \
             the nominal deployment (the table's last line): the margins do not see the \
             chain's dynamics",
            passed_short.join(", "),
            mech.name
        ));
    }
    let unsettled: Vec<String> = nominal
        .as_ref()
        .map(|d| d.unsettled.iter().map(|j| j.to_string()).collect())
        .unwrap_or_default();
    if !unsettled.is_empty() {
        console.warn(format_args!(
            "joint(s) {} of `{}` held at the end of the nominal deployment in one of two runs \
             and not in the other (the second at a tenth of the tolerances): its latches \
             rattle and the outcome is one of several the same wing gives; `deploywatch \
             reliability --fail not_held` with the resistances' spread gives how often it fails",
            unsettled.join(", "),
            mech.name
        ));
    }
    let short: Vec<usize> = short
        .into_iter()
        .chain(
            nominal
                .as_ref()
                .map(|d| d.unsettled.clone())
                .unwrap_or_default(),
        )
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    if args.check && !(failed.is_empty() && short.is_empty()) {
        let mut said = Vec::new();
        if !failed.is_empty() {
            said.push(format!(
                "joint(s) {} of `{}` FAIL",
                failed.join(", "),
                mech.name
            ));
        }
        if !short.is_empty() {
            let short: Vec<String> = short.iter().map(|j| j.to_string()).collect();
            said.push(format!(
                "joint(s) {} of `{}` not held by their latch at the end of the nominal deployment{}",
                short.join(", "),
                mech.name,
                if unsettled.is_empty() {
                    String::new()
                } else {
                    format!(" (joint(s) {} in one of its two runs)", unsettled.join(", "))
                }
            ));
        }
        return Err(CliError::failed(format!(
            "margin --check: {}",
            said.join("; ")
        )));
    }
    Ok(())
}

/// Every joint's margins infinite (nothing resists any joint: no friction
/// in the file, none given, no latch to engage), in a warning: a table a
/// reviewer could sign as a pass on no data.
fn nothing_resists(rows: &[Row]) -> Option<String> {
    let unbounded = |r: &Row| {
        r.margin.torque_margin_pct().is_infinite() && r.margin.energy_margin_pct().is_infinite()
    };
    (!rows.is_empty() && rows.iter().all(unbounded)).then(|| {
        "nothing resists any joint (no friction in the mechanism file, none given by \
         --friction or --from, no latch to engage): every margin is infinite, a pass on no \
         data; give the friction measured or identified"
            .to_string()
    })
}

/// A `--data-source` other than analysis given to standards with one row
/// of factors here: what it changes (nothing) and how to take a lower
/// factor, in a warning.
fn single_row_warning(args: &MarginArgs) -> Option<String> {
    if args.data_source == DataSource::Analysis {
        return None;
    }
    let single: Vec<&str> = if args.all_standards {
        Standard::ALL
            .iter()
            .filter(|s| !s.has_rows())
            .map(|s| s.name())
            .collect()
    } else if args.standard.has_rows() {
        Vec::new()
    } else {
        vec![args.standard.name()]
    };
    (!single.is_empty()).then(|| {
        format!(
            "--data-source {}: {} ha{} one row of factors here, used whatever the source; a \
             resistance measured on the flight hardware takes a lower factor only by --factor \
             KIND=VALUE, your own figure",
            args.data_source.name(),
            single.join(", "),
            if single.len() == 1 { "s" } else { "ve" }
        )
    })
}

/// The warnings of the inputs, before any margin: the mechanism's
/// unlikely values, a `--flight` with nothing to take out, a
/// `--data-source` with no row to select, a `--spring-tolerance` that reads
/// as a fraction, a factor below 1, findings made on another wing.
fn input_warnings(
    args: &MarginArgs,
    mech: &Mechanism,
    resist: &Resistances,
    flight_changes_nothing: bool,
) -> Vec<String> {
    let mut out = crate::model::plausibility::warnings(mech, &args.mechanism);
    if flight_changes_nothing {
        out.push(format!(
            "--flight: {} has no [rig] and nothing is read --from findings: the margins are \
             those of the mechanism as given",
            args.mechanism.display()
        ));
    }
    out.extend(single_row_warning(args));
    out.extend(crate::model::plausibility::percent_as_fraction(
        "--spring-tolerance",
        args.spring_tolerance,
    ));
    for (kind, value) in args.factors.iter().filter(|(_, v)| *v < 1.0) {
        out.push(format!(
            "--factor {kind}={value}: below 1, it takes the {kind} resistance at less than its \
             value, less than any standard's factor"
        ));
    }
    if !resist.found_on.is_empty() && !resist.found_on.contains(&mech.name) {
        out.push(format!(
            "the friction in --from was found on {}, not on {}: it is applied as it is",
            resist.found_on.join(", "),
            mech.name
        ));
    }
    out
}

/// Runs `deploywatch margin`.
pub fn run(args: &MarginArgs) -> Result<(), CliError> {
    // The loader's errors name the file, the key and what was expected.
    let mech = Mechanism::load(&args.mechanism).map_err(|e| CliError::input(e.to_string()))?;
    let flight_changes_nothing = args.flight && mech.rig.is_none() && args.from.is_none();
    let mech = if args.flight { mech.flight() } else { mech };
    let mut resist = match &args.from {
        Some(path) => read_found(path, &mech)
            .map_err(|e| CliError::input(format!("--from {}: {e}", path.display())))?,
        None => given_resistances(args, &mech)?,
    };
    if args.flight {
        resist.take_out_the_rig();
    }
    let inputs: Vec<&std::path::Path> = std::iter::once(&args.mechanism)
        .chain(&args.from)
        .map(|p| p.as_path())
        .collect();
    let outputs: Vec<Output> = (args.json.as_deref().map(|p| Output::file("--json", p)))
        .into_iter()
        .chain(args.plot.as_deref().map(|p| Output::plot("--plot", p)))
        .collect();
    check_outputs(&outputs, &inputs)?;
    let console = Console::new(args.quiet);
    for w in input_warnings(args, &mech, &resist, flight_changes_nothing) {
        console.warn(w);
    }
    let allowance = Allowance::of(&mech, args.spring_tolerance, args.end_of_life);
    if args.all_standards {
        return print_all_standards(args, &mech, &resist, &allowance);
    }
    let (factors, rows) = rows_for(args, &mech, &resist, args.standard, &allowance)?;
    if let Some(w) = nothing_resists(&rows) {
        console.warn(w);
    }
    let dynamic = DynamicMargins::of(&mech, &rows, args.deploy_time, args.standard, &factors)
        .ok_or_else(|| {
            CliError::input(format!(
                "{}: the dynamic margin needs the chain of at most 8 joints",
                args.mechanism.display()
            ))
        })?;
    // Beside the margins, never instead of them: a deployment that cannot
    // be simulated is said so.
    let nominal = NominalDeployment::of(&mech, &resist).map_err(|e| e.to_string());
    let report = MarginReport {
        file: &args.mechanism,
        mech: &mech,
        standard: args.standard,
        factors: &factors,
        resistances: &resist,
        rows: &rows,
        allowance: &allowance,
        data_source: args.data_source,
        dynamic: &dynamic,
        nominal: &nominal,
    };
    super::print_out(format_args!("{}", table(&report)));
    write_outputs(args, &report, &console)?;
    check_nominal(args, &mech, &rows, &dynamic, &nominal, &console)
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
            plot: None,
            all_standards: false,
            quiet: true,
            check: false,
            flight: false,
            spring_tolerance: 0.0,
            end_of_life: 0.0,
            deploy_time: None,
            data_source: DataSource::Analysis,
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
