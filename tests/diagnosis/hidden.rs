//! Hidden effects drawn by the seeded generator, named and measured.

use super::*;

#[test]
fn hidden_effects_are_named_and_measured() {
    let specs = cases();
    assert!(specs.len() >= 60);
    assert!(specs.iter().filter(|s| s.1.len() == 2).count() * 2 >= specs.len() - 1);
    assert!(specs.iter().filter(|s| s.1.is_empty()).count() >= 10);
    let (mut correct, mut total) = (0usize, 0usize);
    let (mut correct2, mut total2) = (0usize, 0usize);
    let mut failures = Vec::new();
    let mut confusion: BTreeMap<(String, String), usize> = BTreeMap::new();
    let mut value_errors = Vec::new();
    let mut gains = Vec::new();
    let mut false_claims_in_null = 0;
    for (seed, kinds, pair) in specs {
        let case = generate(seed, &kinds, pair);
        eprintln!("seed {seed}: diagnosing ({} hidden)", case.truth.len());
        let campaign = campaign_of(&case, |_| true);
        let outcome = diagnose(
            &campaign,
            &deploywatch_tests::diagnose_options(),
            trace_sink(),
        );
        let found = outcome.extended.effects();

        // Only now compare with the truth.
        total += 1;
        let mut want: Vec<_> = case.truth.iter().map(key).collect();
        let mut got: Vec<_> = found.iter().map(key).collect();
        want.sort();
        got.sort();
        let ok = want == got && outcome.unexplained.is_none();
        eprintln!(
            "case {total:>2} seed {seed}: {} truth [{}] found [{}] RMS {:.3} -> {:.4} ({} sims, {:.1} s)",
            if ok { "ok  " } else { "MISS" },
            case.truth.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "),
            found.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "),
            outcome.baseline.rms(),
            outcome.extended.rms(),
            outcome.simulations,
            outcome.wall_s
        );
        if case.truth.len() == 2 {
            total2 += 1;
            correct2 += usize::from(ok);
        }
        if ok {
            correct += 1;
        } else {
            failures.push(format!(
                "seed {seed}: truth {:?} found {:?} (RMS {:.4} -> {:.4}){}",
                case.truth.iter().map(|e| e.to_string()).collect::<Vec<_>>(),
                found.iter().map(|e| e.to_string()).collect::<Vec<_>>(),
                outcome.baseline.rms(),
                outcome.extended.rms(),
                outcome
                    .unexplained
                    .as_ref()
                    .map(|u| format!(", unexplained: {u}"))
                    .unwrap_or_default()
            ));
        }
        let truth_name = if case.truth.is_empty() {
            "(none)".to_string()
        } else {
            case.truth
                .iter()
                .map(|e| e.kind().name())
                .collect::<Vec<_>>()
                .join("+")
        };
        let found_name = if found.is_empty() {
            "(none)".to_string()
        } else {
            let mut f: Vec<_> = found.iter().map(|e| e.kind().name()).collect();
            f.sort();
            f.join("+")
        };
        *confusion.entry((truth_name, found_name)).or_default() += 1;
        if case.truth.is_empty() {
            if !found.is_empty() || outcome.unexplained.is_some() {
                false_claims_in_null += 1;
            }
            continue;
        }
        let gain = outcome.baseline.rms() / outcome.extended.rms().max(1e-12);
        gains.push((seed, gain));
        if ok {
            for t in &case.truth {
                let f = found.iter().find(|f| key(f) == key(t)).unwrap();
                let err = (f.value() - t.value()).abs() / t.value().abs();
                value_errors.push((seed, t.to_string(), f.value(), err));
            }
        }
    }

    println!("\nconfusion (truth -> found):");
    for ((t, f), n) in &confusion {
        println!("  {t:<40} -> {f:<40} {n}");
    }
    println!("\ncorrect set of names and joints: {correct}/{total}");
    println!("  of which two-cause campaigns: {correct2}/{total2}");
    for f in &failures {
        println!("  MISS {f}");
    }
    let worst_value = value_errors.iter().map(|v| v.3).fold(0.0, f64::max);
    println!(
        "value error of the effects named right: worst {:.2} %",
        100.0 * worst_value
    );
    let min_gain = gains.iter().map(|g| g.1).fold(f64::INFINITY, f64::min);
    println!("RMS gain: smallest x{min_gain:.1}");
    let body = format!(
        "## Diagnosis: the hidden-set suite\n\n\
         {total} seeded campaigns of `tests/diagnosis.rs` (`docs/diagnosis.md`, \
         \"How well it works\"): every effect alone, two causes, null campaigns; \
         reference sensor noise.\n\n\
         | criterion | required | measured |\n|---|---|---|\n\
         | exact set of names and joints | ≥ 95 % | {correct}/{total} ({:.1} %) |\n\
         | of which two-cause campaigns | (reported) | {correct2}/{total2} |\n\
         | value error of every effect named right | ≤ 5 % | worst {:.2} % |\n\
         | RMS gain whenever an effect was hidden | ≥ 5× | smallest {min_gain:.1}× |\n\
         | effects claimed in null campaigns | 0 | {false_claims_in_null} |\n",
        100.0 * correct as f64 / total.max(1) as f64,
        100.0 * worst_value,
    );
    deploywatch_tests::record::record(
        "diagnosis-hidden-set",
        "DEPLOYWATCH_FULL=1 cargo test -p deploywatch-tests --test diagnosis hidden_effects -- --nocapture",
        &body,
    )
    .expect("docs/measured.md written");

    assert!(
        correct * 100 >= total * 95,
        "only {correct}/{total} correct"
    );
    for (seed, t, v, err) in &value_errors {
        assert!(
            *err <= 0.05,
            "seed {seed}: {t} estimated {v} ({:.1} % off)",
            100.0 * err
        );
    }
    for (seed, g) in &gains {
        assert!(*g >= 5.0, "seed {seed}: RMS gain only x{g:.2}");
    }
    assert_eq!(false_claims_in_null, 0, "effects claimed in null cases");
}
