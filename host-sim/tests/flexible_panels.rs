//! Flexible panels (`docs/spec/physics.md` §12): the flex joints' stiffness
//! and damping put the deployed wing's first mode where the file says, a
//! stiff panel deploys as the rigid one, and the file's table is read,
//! refused where it cannot be simulated, and written back.
//!
//! `cargo test -p deploywatch-sim --test flexible_panels`

use deploywatch_core::{ChainState, Mode};
use deploywatch_sim::deployment::{simulate, SimOptions};
use deploywatch_sim::flex::PanelFlex;
use deploywatch_sim::mechanism::Mechanism;
use std::path::Path;

fn bundled(name: &str) -> Mechanism {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data/mechanisms")
        .join(name);
    Mechanism::load(&p).expect("bundled mechanism")
}

fn flexible(mut m: Mechanism, hz: f64, zeta: f64) -> Mechanism {
    m.flexible = Some(PanelFlex {
        first_mode_hz: hz,
        damping_ratio: zeta,
    });
    m
}

/// The modes of the flex joints with every hinge latched, from the chain's
/// own equations: the mass matrix at the deployed angles and the
/// stiffness and damping by central differences of the generalised
/// forces. Returns (ω₁ [rad/s], ζ₁) of the lowest mode.
fn lowest_mode<const M: usize>(m: &Mechanism) -> (f64, f64) {
    let chain = m.flexible_chain::<M>(&vec![Default::default(); M / 2], Default::default());
    let chain = chain.expect("flexible chain");
    let mode = Mode::<M> {
        latched: core::array::from_fn(|i| i % 2 == 0),
        ..Mode::default()
    };
    let n = M / 2;
    let force = |phi: [f64; M], rate: [f64; M]| {
        let (_, rhs) = chain.equations(&ChainState { phi, phi_dot: rate }, &mode);
        rhs
    };
    let h = 1e-6;
    let mass = chain.mass_matrix(&[0.0; M]);
    let mut k = nalgebra::DMatrix::zeros(n, n);
    let mut c = nalgebra::DMatrix::zeros(n, n);
    for col in 0..n {
        let (mut up, mut down) = ([0.0; M], [0.0; M]);
        up[2 * col + 1] = h;
        down[2 * col + 1] = -h;
        let (fu, fd) = (force(up, [0.0; M]), force(down, [0.0; M]));
        let (vu, vd) = (force([0.0; M], up), force([0.0; M], down));
        for row in 0..n {
            k[(row, col)] = -(fu[2 * row + 1] - fd[2 * row + 1]) / (2.0 * h);
            c[(row, col)] = -(vu[2 * row + 1] - vd[2 * row + 1]) / (2.0 * h);
        }
    }
    let mff = nalgebra::DMatrix::from_fn(n, n, |r, cc| mass[2 * r + 1][2 * cc + 1]);
    // Mass-normalised: L⁻¹ K L⁻ᵀ with M = L Lᵀ.
    let l = mff.clone().cholesky().expect("M_ff positive").l();
    let li = l.clone().try_inverse().expect("L invertible");
    let kn = &li * &k * li.transpose();
    let eig = nalgebra::SymmetricEigen::new(kn);
    let i = eig.eigenvalues.imin();
    let w2 = eig.eigenvalues[i];
    let v = eig.eigenvectors.column(i).into_owned();
    let cn = &li * &c * li.transpose();
    let modal_c = (v.transpose() * cn * &v)[(0, 0)];
    let w = w2.sqrt();
    (w, modal_c / (2.0 * w))
}

#[test]
fn the_first_mode_is_where_the_file_puts_it() {
    for (name, hz, zeta) in [
        ("seed001_T01.toml", 8.0, 0.02),
        ("seed001_T02.toml", 4.5, 0.01),
        ("seed000_case1.toml", 15.0, 0.03),
    ] {
        let m = flexible(bundled(name), hz, zeta);
        let (w, z) = match m.joint_count() {
            1 => lowest_mode::<2>(&m),
            2 => lowest_mode::<4>(&m),
            3 => lowest_mode::<6>(&m),
            4 => lowest_mode::<8>(&m),
            n => panic!("{name}: {n} joints"),
        };
        let f = w / (2.0 * std::f64::consts::PI);
        assert!(
            (f - hz).abs() < 1e-4 * hz,
            "{name}: first mode {f} Hz, want {hz}"
        );
        assert!(
            (z - zeta).abs() < 1e-4,
            "{name}: damping ratio {z}, want {zeta}"
        );
    }
}

#[test]
fn a_stiff_panel_deploys_as_the_rigid_one() {
    let rigid = bundled("seed001_T01.toml");
    let opts = SimOptions::default();
    let a = simulate(&rigid, &[], &opts).expect("rigid run");
    let mut worst = [0.0_f64; 2];
    for (k, hz) in [40.0, 160.0].into_iter().enumerate() {
        let b = simulate(&flexible(rigid.clone(), hz, 0.02), &[], &opts).expect("flexible run");
        assert_eq!(b.joints(), a.joints(), "the encoders read the hinges");
        assert!(b.deployed(), "{hz} Hz: every hinge latches");
        for j in 0..a.joints() {
            let (la, lb) = (a.latch_s[j].unwrap_or(0.0), b.latch_s[j].unwrap_or(0.0));
            worst[k] = worst[k].max((la - lb).abs());
        }
    }
    eprintln!("latch instants off the rigid wing's at 40 and 160 Hz: {worst:?} s");
    // The flexible wing tends to the rigid one as the panels stiffen:
    // latch instants within 2 ms at 160 Hz, and closer than at 40 Hz.
    assert!(worst[1] < 2e-3, "latch instants {worst:?} s apart");
    assert!(worst[1] < worst[0], "{worst:?}");
}

#[test]
fn the_table_is_read_refused_and_written_back() {
    let base = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/mechanisms/seed001_T01.toml"),
    )
    .expect("bundled file");
    let text = format!("{base}\n[flexible_panels]\nfirst_mode_hz = 7.5\n");
    let m = Mechanism::from_toml_str(&text, "flex.toml").expect("valid");
    let f = m.flexible.expect("read");
    assert_eq!(f.first_mode_hz, 7.5);
    assert_eq!(
        f.damping_ratio,
        deploywatch_sim::flex::DEFAULT_DAMPING_RATIO
    );
    let back = Mechanism::from_toml_str(&m.to_toml_string(), "back.toml").expect("written");
    assert_eq!(back, m);

    for (extra, want) in [
        ("first_mode_hz = 0", "first_mode_hz"),
        ("first_mode_hz = 5\ndamping_ratio = 1.5", "damping_ratio"),
        ("damping_ratio = 0.02", "first_mode_hz"),
        ("first_mode_hz = 5\nmode = 3", "mode"),
    ] {
        let text = format!("{base}\n[flexible_panels]\n{extra}\n");
        let e = Mechanism::from_toml_str(&text, "flex.toml").expect_err(extra);
        let msg = e.to_string();
        assert!(msg.contains(want), "{extra}: {msg}");
        assert!(e.line.is_some(), "{extra}: no line in {msg}");
    }
    let physical = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../data/mechanisms/seed001_T01_physical_latch.toml"),
    )
    .expect("bundled file");
    let text = format!("{physical}\n[flexible_panels]\nfirst_mode_hz = 7.5\n");
    let msg = Mechanism::from_toml_str(&text, "flex.toml")
        .expect_err("physical latch")
        .to_string();
    assert!(msg.contains("physical latch"), "{msg}");
}
