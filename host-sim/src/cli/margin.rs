//! `deploywatch margin`: the torque margins of every joint of a mechanism
//! (`docs/margin.md`, `physics.md` 9).
//!
//! For each joint it prints `T_D` (the spring torque at the stowed angle on
//! the unfolding branch), `T_R` (the friction: `--friction` or the joint's
//! `friction.coulomb_nm`), the torque-form margin (seed 001 Eq. 7), `E_D`,
//! `E_R = T_R · stroke` and the energy-form margin (seed 000 Eq. 21), with the
//! chosen standard's friction factor applied, and pass/fail against its
//! required minimum.

use super::CliError;
use crate::analysis::design_margin::{joint_margin, JointMargin, NameError, Resistance, Standard};
use crate::model::mechanism::Mechanism;
use std::path::PathBuf;

/// Arguments of `deploywatch margin`.
#[derive(clap::Args, Debug)]
pub struct MarginArgs {
    /// Mechanism file (TOML, docs/spec/formats.md).
    #[arg(long, value_name = "M.toml")]
    pub mechanism: PathBuf,

    /// Friction (EFT) per joint [N·m], comma-separated, one value per joint
    /// (e.g. 0.54,0.472); default: each joint's friction.coulomb_nm.
    #[arg(long, value_name = "NM,NM,..", value_delimiter = ',')]
    pub friction: Option<Vec<f64>>,

    /// Flight standard whose uncertainty factors and minimum margin apply.
    #[arg(long, default_value = "none", value_parser = parse_standard)]
    pub standard: Standard,

    /// Override one uncertainty factor, KIND=VALUE (kinds: inertia, spring,
    /// friction, hysteresis, harness, adhesion, other); may be repeated.
    #[arg(long = "factor", value_name = "KIND=VALUE", value_parser = parse_factor)]
    pub factors: Vec<(Resistance, f64)>,
}

fn parse_standard(s: &str) -> Result<Standard, String> {
    s.parse().map_err(|e: NameError| e.to_string())
}

fn parse_factor(s: &str) -> Result<(Resistance, f64), String> {
    let (k, v) = s
        .split_once('=')
        .ok_or_else(|| format!("`{s}`: expected KIND=VALUE, e.g. friction=2.5"))?;
    let kind: Resistance = k.parse().map_err(|e: NameError| e.to_string())?;
    let value: f64 = v
        .trim()
        .parse()
        .map_err(|_| format!("`{v}` is not a number"))?;
    if !(value.is_finite() && value > 0.0) {
        return Err(format!("factor `{v}` must be a positive number"));
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

/// Runs `deploywatch margin`.
pub fn run(args: &MarginArgs) -> Result<(), CliError> {
    // The loader's errors name the file, the key and what was expected.
    let mech = Mechanism::load(&args.mechanism).map_err(|e| CliError::input(e.to_string()))?;
    let n = mech.joint_count();
    let friction: Vec<f64> = match &args.friction {
        Some(v) => {
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
            v.clone()
        }
        None => mech.joints.iter().map(|j| j.friction.coulomb_nm).collect(),
    };
    let mut factors = args.standard.factors();
    for (kind, value) in &args.factors {
        factors.set(*kind, *value);
    }
    let custom = factors != args.standard.factors();

    let mut rows = Vec::with_capacity(n);
    for (j, joint) in mech.joints.iter().enumerate() {
        let spring = joint.spring.to_spring().map_err(|e| {
            CliError::input(format!(
                "{}: joint {}: bad spring: {e}",
                args.mechanism.display(),
                j + 1
            ))
        })?;
        let m = joint_margin(
            &spring,
            joint.stowed_deg.to_radians(),
            friction[j],
            args.standard,
            Some(&factors),
        );
        rows.push((j + 1, joint.stowed_deg, m));
    }

    println!(
        "torque margins of `{}` ({})",
        mech.name,
        args.mechanism.display()
    );
    println!(
        "standard: {}{}",
        args.standard.reference(),
        if custom { " (factors overridden)" } else { "" }
    );
    if args.standard != Standard::None || custom {
        let list: Vec<String> = Resistance::ALL
            .iter()
            .map(|r| format!("{r} {}", factors.get(*r)))
            .collect();
        println!("uncertainty factors: {}", list.join(", "));
        println!(
            "applied to the friction: {} ; required minimum margin: {:.0} %",
            factors.get(Resistance::Friction),
            args.standard.required_margin() * 100.0
        );
        println!("margins below: D / (FoS_friction · R) − 1");
    } else {
        println!("margins below: D / R − 1 (seed 001 Eq. 7, seed 000 Eq. 21); pass at ≥ 0 %");
    }
    println!();
    println!(
        "{:>5} {:>10} {:>9} {:>9} {:>11} {:>9} {:>9} {:>11}  result",
        "joint", "stowed_deg", "T_D_Nm", "T_R_Nm", "TM_torque_%", "E_D_J", "E_R_J", "TM_energy_%",
    );
    for (j, stowed, m) in &rows {
        println!(
            "{:>5} {:>10.2} {:>9.4} {:>9.4} {:>11} {:>9.4} {:>9.4} {:>11}  {}",
            j,
            stowed,
            m.driving_torque_nm,
            m.resisting_torque_nm,
            pct(m.torque_margin_pct()),
            m.driving_energy_j,
            m.resisting_energy_j,
            pct(m.energy_margin_pct()),
            verdict(m)
        );
    }
    Ok(())
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
        assert_eq!(
            parse_standard("ECSS-E-ST-33-01C").unwrap(),
            Standard::EcssEST3301C
        );
        assert!(parse_standard("mil-std").is_err());
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
            standard: Standard::EcssEST3301C,
            factors: vec![(Resistance::Friction, 2.5)],
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
