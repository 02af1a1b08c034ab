//! Instructions per call of `core::linalg` and of its nalgebra equivalents
//! on the Cortex-M4F (QEMU mps2-an386, `-icount shift=0`), on the mass
//! matrices of the firmware's chains, and whether they agree.
//!
//! Inputs: the mass matrix `M(φ)` and right-hand side of
//! `Chain::<f32, N>::equations` for N = 2 and 3 (panels of 0.8 m, 3.5 kg,
//! linear springs) at folded, half-way and deployed angles, under every mask
//! of locked joints (all free … all locked), plus a zero matrix (not
//! positive definite). Each function runs [`REPS`] times on each input; the
//! count is SysTick ticks on the core clock × instructions per tick (40:
//! 25 MHz, 1 ns per instruction), less an empty loop's, divided by
//! [`REPS`]. Prints the mean and the largest over the inputs.
//!
//! Agreement: every result of nalgebra must be within [`TOL`] (relative to
//! the largest entry) of the core's, and both must fail on the same inputs;
//! the locked entries of a solve must both be exactly 0. Exits 1 otherwise.
#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;
use cortex_m_rt::entry;
use deploywatch_core::{
    Chain, ChainState, Friction, GlobalEffects, Joint, JointEffects, Mode, Panel, Spring,
};
use linalg_nalgebra::{core_impl as c, nalgebra_impl as n};
use nalgebra::{SMatrix, SVector};
use semihosting::{print, println, process};

/// Calls per input and function.
const REPS: u32 = 500;
/// Largest accepted difference, relative to the largest entry: a few `f32`
/// roundings (6e-8 each) amplified by the factorisation, with room to spare.
const TOL: f32 = 1e-4;
/// SysTick's reload: its full 24 bits.
const RELOAD: u32 = 0x00ff_ffff;

/// An input of the N-joint functions.
struct Case<const N: usize> {
    m: [[f32; N]; N],
    b: [f32; N],
    locked: [bool; N],
}

fn chain<const N: usize>() -> Chain<f32, N> {
    let p = Panel {
        length_m: 0.8,
        mass_kg: 3.5,
        com_m: 0.4,
        inertia_kgm2: 0.27,
    };
    let j = Joint {
        stowed_rad: 1.0,
        spring: Spring::Linear {
            preload_nm: 1.0,
            stiffness_nm_per_rad: 0.5,
            count: 1.0,
        },
        friction: Friction::default(),
        effects: JointEffects::default(),
    };
    match Chain::new([p; N], [j; N], GlobalEffects::default()) {
        Ok(c) => c,
        Err(_) => fail("the chain cannot be built"),
    }
}

/// Every mask of N joints (bit k of the index locks joint k), at three
/// configurations, then the zero matrix.
fn cases<const N: usize>(out: &mut [Case<N>]) -> usize {
    let ch = chain::<N>();
    let mut k = 0;
    // Folded, half-way, deployed [rad].
    let configs: [[f32; 3]; 3] = [[1.5, -2.9, 2.9], [0.75, -1.45, 1.45], [0.0, 0.0, 0.0]];
    for phi3 in configs {
        let mut phi = [0.0f32; N];
        let mut rate = [0.0f32; N];
        for i in 0..N {
            phi[i] = phi3[i];
            rate[i] = 0.4 * (i as f32 + 1.0) * if i % 2 == 0 { 1.0 } else { -1.0 };
        }
        let x = ChainState { phi, phi_dot: rate };
        for mask in 0..(1u32 << N) {
            let mut locked = [false; N];
            for (i, l) in locked.iter_mut().enumerate() {
                *l = mask & (1 << i) != 0;
            }
            let (m, b) = ch.equations(&x, &Mode::default());
            if let Some(slot) = out.get_mut(k) {
                *slot = Case { m, b, locked };
                k += 1;
            }
        }
    }
    if let Some(slot) = out.get_mut(k) {
        *slot = Case {
            m: [[0.0; N]; N],
            b: [1.0; N],
            locked: [false; N],
        };
        k += 1;
    }
    k
}

fn fail(why: &str) -> ! {
    println!("linalg-eval: {}", why);
    process::exit(1)
}

/// Instructions per SysTick tick, from a loop of known length (as
/// firmware-example's `calibrate`).
fn calibrate() -> u32 {
    // `asm::delay(n)` runs n + 1 turns of a two-instruction loop.
    const TURNS: u32 = 100_000;
    let t0 = SYST::get_current();
    cortex_m::asm::delay(TURNS - 1);
    let ticks = ticks_since(t0).max(1);
    (2 * TURNS + ticks / 2) / ticks
}

fn ticks_since(t0: u32) -> u32 {
    t0.wrapping_sub(SYST::get_current()) & RELOAD
}

/// Instructions of `REPS` calls of `f`, less those of the empty loop.
struct Meter {
    per_tick: u32,
    empty: u32,
}

impl Meter {
    fn ticks<R>(&self, mut f: impl FnMut() -> R) -> u32 {
        let t0 = SYST::get_current();
        for _ in 0..REPS {
            black_box(f());
        }
        ticks_since(t0)
    }

    /// Instructions per call of `f` [instructions, ×10 for one decimal].
    fn per_call_x10<R>(&self, f: impl FnMut() -> R) -> u32 {
        let ins = self.ticks(f) * self.per_tick;
        (10 * ins.saturating_sub(self.empty) + REPS / 2) / REPS
    }
}

/// Mean and largest instructions per call over the inputs.
#[derive(Default, Clone, Copy)]
struct Tally {
    n: u32,
    sum_x10: u32,
    max_x10: u32,
}

impl Tally {
    fn add(&mut self, x10: u32) {
        self.n += 1;
        self.sum_x10 += x10;
        self.max_x10 = self.max_x10.max(x10);
    }
}

fn row(what: &str, nj: usize, a: Tally, b: Tally, b_name: &str) {
    let mean = |t: Tally| t.sum_x10 / t.n.max(1);
    let f = |x10: u32| (x10 / 10, x10 % 10);
    let (am, ad) = f(mean(a));
    let (ax, axd) = f(a.max_x10);
    let (bm, bd) = f(mean(b));
    let (bx, bxd) = f(b.max_x10);
    println!(
        "| {} | {} | {}.{} | {}.{} | {} | {}.{} | {}.{} | {:+} % |",
        what,
        nj,
        am,
        ad,
        ax,
        axd,
        b_name,
        bm,
        bd,
        bx,
        bxd,
        (100 * (mean(b) as i64 - mean(a) as i64)) / (mean(a) as i64).max(1)
    );
}

/// Largest difference between two answers relative to the largest entry;
/// `None` when one failed and the other did not, or a locked entry differs
/// from zero.
fn diff<const N: usize>(
    a: Option<[f32; N]>,
    b: Option<[f32; N]>,
    locked: &[bool; N],
) -> Option<f32> {
    match (a, b) {
        (None, None) => Some(0.0),
        (Some(a), Some(b)) => {
            let mut scale = 0.0f32;
            let mut d = 0.0f32;
            for i in 0..N {
                if locked[i] && (a[i] != 0.0 || b[i] != 0.0) {
                    return None;
                }
                scale = scale.max(abs(a[i]));
                d = d.max(abs(a[i] - b[i]));
            }
            Some(if scale > 0.0 { d / scale } else { d })
        }
        _ => None,
    }
}

fn abs(x: f32) -> f32 {
    if x < 0.0 {
        -x
    } else {
        x
    }
}

fn opt_diff(a: Option<f32>, b: Option<f32>) -> Option<f32> {
    diff(a.map(|x| [x]), b.map(|x| [x]), &[false])
}

/// The largest disagreement of one function over the inputs; fails the run
/// beyond [`TOL`] or on a different failure.
struct Agree {
    worst: f32,
    cases: u32,
}

impl Agree {
    fn new() -> Self {
        Agree {
            worst: 0.0,
            cases: 0,
        }
    }
    fn check(&mut self, what: &str, nj: usize, d: Option<f32>) {
        self.cases += 1;
        match d {
            Some(d) if d <= TOL => self.worst = self.worst.max(d),
            Some(d) => {
                println!("{} N={}: relative difference {:e}", what, nj, d);
                fail("the implementations disagree");
            }
            None => {
                println!("{} N={}: one fails where the other does not", what, nj);
                fail("the implementations disagree");
            }
        }
    }
}

macro_rules! measure {
    ($nj:literal, $solve:ident, $solve_lu:ident, $inertias:ident, $inertia:ident, $mat_vec:ident, $mat_vec_native:ident, $mat_vec_rows:ident, $meter:expr, $agree:expr, $rows:expr) => {{
        let mut store: [Case<$nj>; 3 * (1 << $nj) + 1] = core::array::from_fn(|_| Case {
            m: [[0.0; $nj]; $nj],
            b: [0.0; $nj],
            locked: [false; $nj],
        });
        let k = cases::<$nj>(&mut store);
        let cs = &store[..k];
        let meter: &Meter = $meter;
        let agree: &mut [Agree; 5] = $agree;
        let mut t = [[Tally::default(); 2]; 7];
        for cs in cs {
            let (m, b, l) = (&cs.m, &cs.b, &cs.locked);
            // solve: core, nalgebra Cholesky, nalgebra LU.
            t[0][0].add(meter.per_call_x10(|| c::$solve(black_box(m), black_box(b), black_box(l))));
            t[0][1].add(meter.per_call_x10(|| n::$solve(black_box(m), black_box(b), black_box(l))));
            t[1][0] = t[0][0];
            t[1][1]
                .add(meter.per_call_x10(|| n::$solve_lu(black_box(m), black_box(b), black_box(l))));
            agree[0].check(
                "solve (Cholesky)",
                $nj,
                diff(c::$solve(m, b, l), n::$solve(m, b, l), l),
            );
            agree[1].check(
                "solve (LU)",
                $nj,
                diff(c::$solve(m, b, l), n::$solve_lu(m, b, l), l),
            );
            // articulated inertias.
            t[2][0].add(meter.per_call_x10(|| c::$inertias(black_box(m), black_box(l))));
            t[2][1].add(meter.per_call_x10(|| n::$inertias(black_box(m), black_box(l))));
            let (ic, ina) = (c::$inertias(m, l), n::$inertias(m, l));
            for j in 0..$nj {
                agree[2].check("articulated_inertias", $nj, opt_diff(ic[j], ina[j]));
            }
            // one articulated inertia, of each joint.
            for j in 0..$nj {
                t[3][0].add(
                    meter.per_call_x10(|| c::$inertia(black_box(m), black_box(l), black_box(j))),
                );
                t[3][1].add(
                    meter.per_call_x10(|| n::$inertia(black_box(m), black_box(l), black_box(j))),
                );
                agree[3].check(
                    "articulated_inertia",
                    $nj,
                    opt_diff(c::$inertia(m, l, j), n::$inertia(m, l, j)),
                );
            }
            // M x.
            t[4][0].add(meter.per_call_x10(|| c::$mat_vec(black_box(m), black_box(b))));
            t[4][1].add(meter.per_call_x10(|| n::$mat_vec(black_box(m), black_box(b))));
            agree[4].check(
                "mat_vec",
                $nj,
                diff(
                    Some(c::$mat_vec(m, b)),
                    Some(n::$mat_vec(m, b)),
                    &[false; $nj],
                ),
            );
            // M x on nalgebra's own types, converted before the count.
            let (a, x) = (
                SMatrix::<f32, $nj, $nj>::from_fn(|i, j| m[i][j]),
                SVector::<f32, $nj>::from(*b),
            );
            t[5][0] = t[4][0];
            t[5][1].add(meter.per_call_x10(|| n::$mat_vec_native(black_box(&a), black_box(&x))));
            agree[4].check(
                "mat_vec",
                $nj,
                diff(
                    Some(c::$mat_vec(m, b)),
                    Some(n::$mat_vec_native(&a, &x).into()),
                    &[false; $nj],
                ),
            );
            // M x on the core's arrays, one dot product per row: must be
            // bit-identical with the core's.
            t[6][0] = t[4][0];
            t[6][1].add(meter.per_call_x10(|| c::$mat_vec_rows(black_box(m), black_box(b))));
            if c::$mat_vec_rows(m, b) != c::$mat_vec(m, b) {
                fail("mat_vec_rows is not bit-identical with mat_vec");
            }
        }
        let rows: &mut [(&str, usize, Tally, Tally, &str); 14] = $rows;
        let i0 = if $nj == 2 { 0 } else { 7 };
        rows[i0] = (
            "solve_spd_masked",
            $nj,
            t[0][0],
            t[0][1],
            "Cholesky::new + solve",
        );
        rows[i0 + 1] = ("solve_spd_masked", $nj, t[1][0], t[1][1], "lu() + solve");
        rows[i0 + 2] = (
            "articulated_inertias",
            $nj,
            t[2][0],
            t[2][1],
            "Cholesky::new + inverse",
        );
        rows[i0 + 3] = (
            "articulated_inertia",
            $nj,
            t[3][0],
            t[3][1],
            "Cholesky::new + solve(e_j)",
        );
        rows[i0 + 4] = ("mat_vec", $nj, t[4][0], t[4][1], "SMatrix * SVector");
        rows[i0 + 5] = (
            "mat_vec",
            $nj,
            t[5][0],
            t[5][1],
            "SMatrix * SVector, SMatrix inputs",
        );
        rows[i0 + 6] = (
            "mat_vec",
            $nj,
            t[6][0],
            t[6][1],
            "(no nalgebra) arrays, a dot product per row",
        );
        k
    }};
}

#[entry]
fn main() -> ! {
    let Some(mut p) = cortex_m::Peripherals::take() else {
        fail("the core peripherals are already taken");
    };
    let syst = &mut p.SYST;
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(RELOAD);
    syst.clear_current();
    syst.enable_counter();
    let per_tick = calibrate();
    let mut meter = Meter { per_tick, empty: 0 };
    meter.empty = meter.ticks(|| black_box(0u32)) * per_tick;
    let mut agree = [
        Agree::new(),
        Agree::new(),
        Agree::new(),
        Agree::new(),
        Agree::new(),
    ];
    let mut rows = [("", 0usize, Tally::default(), Tally::default(), ""); 14];
    // What the harness costs around a call: an out-of-line function of the
    // same arguments that only copies its vector.
    let (fm, fx) = ([[1.0f32; 3]; 3], [1.0f32; 3]);
    let floor = meter.per_call_x10(|| floor(black_box(&fm), black_box(&fx)));
    let k2 = measure!(
        2,
        solve2,
        solve_lu2,
        inertias2,
        inertia2,
        mat_vec2,
        mat_vec_native2,
        mat_vec_rows2,
        &meter,
        &mut agree,
        &mut rows
    );
    let k3 = measure!(
        3,
        solve3,
        solve_lu3,
        inertias3,
        inertia3,
        mat_vec3,
        mat_vec_native3,
        mat_vec_rows3,
        &meter,
        &mut agree,
        &mut rows
    );
    println!(
        "instructions per call, f32, Cortex-M4F (QEMU mps2-an386 -icount shift=0, {} per SysTick tick, {} calls per input), over {} inputs (N = 2) and {} (N = 3):",
        per_tick, REPS, k2, k3
    );
    println!();
    println!("| function | N | core mean | core max | nalgebra | nalgebra mean | nalgebra max | mean change |");
    println!("|---|---|---|---|---|---|---|---|");
    for (what, nj, a, b, name) in rows {
        row(what, nj, a, b, name);
    }
    println!();
    println!(
        "(every count includes the call and the harness's argument set-up: {}.{} for an out-of-line function of the same arguments that returns a copy of its [f32; 3])",
        floor / 10,
        floor % 10
    );
    println!();
    print!("agreement (largest difference relative to the largest entry, both fail on the same inputs, locked entries exactly 0):");
    let names = [
        "solve (Cholesky)",
        "solve (LU)",
        "articulated_inertias",
        "articulated_inertia",
        "mat_vec",
    ];
    for (name, a) in names.iter().zip(&agree) {
        print!(" {} {:.1e} ({} checks);", name, a.worst, a.cases);
    }
    println!();
    process::exit(0)
}

/// The harness's floor: a call that does nothing but copy.
#[inline(never)]
fn floor(m: &[[f32; 3]; 3], x: &[f32; 3]) -> [f32; 3] {
    black_box(m);
    *x
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    println!("linalg-eval: {}", info);
    process::exit(101)
}
