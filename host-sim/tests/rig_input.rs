//! A `[rig]` a new user gets wrong is refused when the file is read, at
//! the line of the key that is wrong, saying what it should be: a frame
//! the stowed wing already crosses, an offload point off its panel, a load
//! share above one, friction and indices out of range.
//!
//! `cargo test -p deploywatch-sim --test rig_input`
use deploywatch_sim::mechanism::Mechanism;

/// Two 0.8 m panels stowed at `phi1`, `phi2` \[deg\], each on a trolley of
/// bar 1, `extra` appended to `[rig]`'s trolleys and frames.
fn two_panels(phi1: f64, phi2: f64, rig: &str, extra: &str) -> String {
    format!(
        r#"name = "rig-input"
[[panel]]
length_m = 0.8
mass_kg = 3.5
com_m = 0.4
inertia_kgm2 = 0.27
[[panel]]
length_m = 0.8
mass_kg = 3.5
com_m = 0.4
inertia_kgm2 = 0.27
[[joint]]
stowed_deg = {phi1}
spring = {{ kind = "linear", preload_nm = 1.5, stiffness_nm_per_rad = 0.5, count = 1 }}
[[joint]]
stowed_deg = {phi2}
spring = {{ kind = "linear", preload_nm = 0.6, stiffness_nm_per_rad = 0.3, count = 1 }}
[run]
duration_s = 3.0
[rig]
{rig}
[[rig.bar]]
mass_kg = 2.0
[[rig.trolley]]
panel = 1
bar = 1
mass_kg = 0.5
wire_m = 1.5
[[rig.trolley]]
panel = 2
bar = 1
mass_kg = 0.5
wire_m = 1.5
{extra}"#
    )
}

/// The 1-based line of the last line of `text` that starts with `key`.
fn line_of(text: &str, key: &str) -> usize {
    let lines: Vec<&str> = text.lines().collect();
    1 + lines
        .iter()
        .rposition(|l| l.starts_with(key))
        .expect("key in text")
}

/// The error reading `text`, checked to be at `key`'s (last) line.
fn refused_at(text: &str, key: &str) -> String {
    let e = Mechanism::from_toml_str(text, "rig.toml")
        .expect_err("refused")
        .to_string();
    let at = format!("rig.toml:{}:", line_of(text, key));
    assert!(e.starts_with(&at), "expected at {at}\n{e}\n{text}");
    assert!(!e.contains("found a table"), "{e}");
    e
}

/// The tips of the two panels stowed at `phi1`, `phi2` \[deg\]: the
/// planar chain of `physics.md` §1, absolute angle the sum of the joints'.
fn tips(phi1: f64, phi2: f64) -> [[f64; 2]; 2] {
    let (a1, a2) = (phi1.to_radians(), (phi1 + phi2).to_radians());
    let p1 = [0.8 * a1.cos(), 0.8 * a1.sin()];
    [p1, [p1[0] + 0.8 * a2.cos(), p1[1] + 0.8 * a2.sin()]]
}

#[test]
fn a_frame_the_stowed_wing_crosses_is_refused_at_its_face_and_one_clear_of_it_is_not() {
    // Every fold of the two joints on a 30-degree grid (0 is no stroke),
    // and a frame on each side (±x, ±y) 5 mm through the outermost tip,
    // then 5 mm clear.
    let mut checked = 0;
    for i in (1..12).filter(|&i| i != 6) {
        for k in (1..12).filter(|&k| k != 6) {
            let (phi1, phi2) = (-180.0 + 30.0 * f64::from(i), -180.0 + 30.0 * f64::from(k));
            let t = tips(phi1, phi2);
            for normal in [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]] {
                let along = |p: [f64; 2]| normal[0] * p[0] + normal[1] * p[1];
                let (deepest, low) = if along(t[0]) <= along(t[1]) {
                    (1, along(t[0]))
                } else {
                    (2, along(t[1]))
                };
                // Two tips as deep (to a micrometre) are left out: the
                // rounding decides which is named.
                if (along(t[0]) - along(t[1])).abs() < 1e-6 {
                    continue;
                }
                let frame = |at: f64| {
                    format!(
                        "[[rig.frame]]\nname = \"f\"\nnormal = [{:.1}, {:.1}]\nat_m = {at}\n",
                        normal[0], normal[1]
                    )
                };
                let through = two_panels(phi1, phi2, "", &frame(low + 0.005));
                let e = refused_at(&through, "at_m");
                assert!(
                    e.contains(&format!("panel {deepest}'s tip is 5.0 mm beyond")),
                    "{e}"
                );
                let clear = two_panels(phi1, phi2, "", &frame(low - 0.005));
                Mechanism::from_toml_str(&clear, "rig.toml").expect("a frame clear of the wing");
                checked += 1;
            }
        }
    }
    assert!(checked > 300, "{checked} cases");
}

#[test]
fn an_offload_point_off_its_panel_is_refused_at_its_line() {
    for at in [-0.1, 0.81, 1.5] {
        let text = two_panels(-90.0, 180.0, "", "").replacen(
            "panel = 2\n",
            &format!("panel = 2\noffload_m = {at}\n"),
            1,
        );
        let e = refused_at(&text, "offload_m");
        assert!(e.contains("off panel 2") && e.contains("0.8 m"), "{e}");
    }
    for at in [0.0, 0.3, 0.8] {
        let text = two_panels(-90.0, 180.0, "", "").replacen(
            "panel = 2\n",
            &format!("panel = 2\noffload_m = {at}\n"),
            1,
        );
        Mechanism::from_toml_str(&text, "rig.toml").expect("on the panel");
    }
}

#[test]
fn rig_values_out_of_range_are_refused_at_their_own_line() {
    let cases = [
        (
            "friction_load_fraction = 1.5",
            "friction_load_fraction",
            "whole",
        ),
        ("static_mu = 0.1\ndynamic_mu = 0.2", "dynamic_mu", "exceeds"),
    ];
    for (rig, key, says) in cases {
        let e = refused_at(&two_panels(-90.0, 180.0, rig, ""), key);
        assert!(e.contains(says), "{e}");
    }
    let bar = two_panels(-90.0, 180.0, "", "").replacen("bar = 1\n", "bar = 3\n", 1);
    let e = refused_at(&bar, "bar = 3");
    assert!(e.contains("the rig has only bar 1"), "{e}");
    let panel = two_panels(-90.0, 180.0, "", "").replacen("panel = 2\n", "panel = 1\n", 1);
    let line = line_of(&panel, "panel = 1");
    let e = Mechanism::from_toml_str(&panel, "rig.toml")
        .expect_err("panel 1 twice")
        .to_string();
    assert!(e.starts_with(&format!("rig.toml:{line}:")), "{e}");
    // In range: accepted.
    Mechanism::from_toml_str(
        &two_panels(-90.0, 180.0, "friction_load_fraction = 0.4", ""),
        "rig.toml",
    )
    .expect("a share of the load");
}
