//! `deploywatch hil`: a recorded run streamed in real time to the
//! serial-link firmware (QEMU over TCP, or a board on a serial device),
//! with the statuses timed and checked against the host core.

use super::{outln, CliError, Console, Output};
use crate::data::run::Run;
use crate::model::mechanism::Mechanism;
use crate::onboard::hil::{self, Assessment, Fate, Inject, Outgoing, Plan, Received};
use crate::onboard::hil_link::{self, Endpoint};
use crate::onboard::replay::{self, ReplayError};
use deploywatch_core::telemetry::link::LinkReport;
use std::path::PathBuf;
use std::time::Duration;

/// Where the serial-link firmware runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum HilTarget {
    /// QEMU's mps2-an386, started here, UART0 over a local TCP socket.
    Qemu,
    /// A board on a serial device (`--port`).
    Serial,
}

/// Arguments of `deploywatch hil`.
#[derive(Debug, clap::Args)]
pub struct HilArgs {
    /// The run (CSV, docs/spec/formats.md); its samples are sent at their
    /// own time stamps.
    pub run: PathBuf,
    /// The run's mechanism (TOML).
    #[arg(long)]
    pub mechanism: PathBuf,
    /// Where the firmware runs: `qemu` (started here) or `serial` (a board
    /// on `--port`; the default when `--port` is given).
    #[arg(long, value_enum)]
    pub target: Option<HilTarget>,
    /// A serial device to a board running the serial-link firmware (e.g.
    /// /dev/ttyACM0).
    #[arg(long, value_name = "DEVICE")]
    pub port: Option<String>,
    /// The serial device's rate in baud (the firmware's board.rs BAUD).
    #[arg(long, default_value_t = 921_600)]
    pub baud: u32,
    /// The serial-link firmware ELF for QEMU (`scripts/firmware.sh build`);
    /// by default firmware-example/target/thumbv7em-none-eabihf/release/deploywatch-firmware-uart
    /// for 3 joints, `deploywatch-firmware-uart-6` for 6.
    #[arg(long, value_name = "ELF")]
    pub elf: Option<PathBuf>,
    /// QEMU's `-icount shift=N,align=on` (guest time aligned to the wall
    /// clock at 2^N ns an instruction); without it no icount.
    #[arg(long, value_name = "N")]
    pub icount: Option<u8>,
    /// Send only the first SECONDS of the run.
    #[arg(long, value_name = "SECONDS")]
    pub duration: Option<f64>,
    /// Send every K-th sample only: the run decimated to 1/K of its rate
    /// (the host's reference is fed the same samples). For the rate at
    /// which deadline misses start.
    #[arg(long, value_name = "K", default_value_t = 1)]
    pub every: usize,
    /// Probability that a sample frame is not sent (0 to 1).
    #[arg(long, default_value_t = 0.0)]
    pub drop: f64,
    /// Probability that a sample frame is sent with one byte changed.
    #[arg(long, default_value_t = 0.0)]
    pub corrupt: f64,
    /// Delay some frames: PROBABILITY:MILLISECONDS (the frames after a
    /// delayed one wait for it).
    #[arg(long, value_name = "P:MS")]
    pub delay: Option<String>,
    /// Seed of the injected loss, corruption and delay.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Fail (exit 1) when a status comes later than one sample period.
    #[arg(long)]
    pub require_deadlines: bool,
    /// Write the statuses that came back as CSV (the columns of `replay`).
    #[arg(long, short, value_name = "STATUS.csv")]
    pub out: Option<PathBuf>,
    /// Draw angles, friction estimates and margins into this PNG.
    #[arg(long, value_name = "PNG")]
    pub plot: Option<PathBuf>,
    /// Write each sample's fate, send time and latency as CSV.
    #[arg(long, value_name = "LATENCY.csv")]
    pub latency: Option<PathBuf>,
    /// Write the firmware's raw defmt log here (QEMU only; decode with
    /// `defmt-print -e ELF < LOG`).
    #[arg(long, value_name = "LOG")]
    pub log: Option<PathBuf>,
    /// No chatter: the verdict, errors and warnings only.
    #[arg(long, short)]
    pub quiet: bool,
}

fn cli_error(e: ReplayError) -> CliError {
    match e {
        ReplayError::Input(_) | ReplayError::Setup(_) => CliError::input(e.to_string()),
        _ => CliError::failed(e.to_string()),
    }
}

/// `--delay P:MS` as (probability, seconds).
fn parse_delay(s: &str) -> Result<(f64, f64), CliError> {
    let bad = || {
        CliError::input(format!(
            "--delay {s}: expected PROBABILITY:MILLISECONDS, e.g. 0.01:5"
        ))
    };
    let (p, ms) = s.split_once(':').ok_or_else(bad)?;
    let p: f64 = p.trim().parse().map_err(|_| bad())?;
    let ms: f64 = ms.trim().parse().map_err(|_| bad())?;
    if !((0.0..=1.0).contains(&p) && ms.is_finite() && ms >= 0.0) {
        return Err(bad());
    }
    Ok((p, ms / 1000.0))
}

/// The injection the arguments ask for.
fn injection(args: &HilArgs) -> Result<Inject, CliError> {
    for (flag, p) in [("--drop", args.drop), ("--corrupt", args.corrupt)] {
        if !(0.0..=1.0).contains(&p) {
            return Err(CliError::input(format!(
                "{flag} {p}: a probability, 0 to 1"
            )));
        }
    }
    let (delay, delay_s) = match &args.delay {
        Some(d) => parse_delay(d)?,
        None => (0.0, 0.0),
    };
    Ok(Inject {
        drop: args.drop,
        corrupt: args.corrupt,
        delay,
        delay_s,
        seed: args.seed,
    })
}

/// Loads the inputs and plans the stream (cut to `--duration`).
fn prepare(args: &HilArgs) -> Result<(Mechanism, Run, Plan), CliError> {
    let mech = Mechanism::load(&args.mechanism).map_err(|e| CliError::input(e.to_string()))?;
    let mut run = replay::load_run(&args.run).map_err(cli_error)?;
    let warnings = crate::data::inputs::check_pair(&mech, &args.mechanism, &run, &args.run)
        .map_err(|e| CliError::input(e.to_string()))?;
    let console = super::Console::new(args.quiet);
    for w in warnings.into_iter().chain(replay::rig_note(&mech)) {
        console.warn(w);
    }
    if args.every == 0 {
        return Err(CliError::input("--every 0: a whole number from 1"));
    }
    if args.every > 1 {
        decimate(&mut run, args.every);
    }
    let joints = mech.joint_count();
    if args.port.is_none() && args.elf.is_none() && !hil_link::UART_JOINTS.contains(&joints) {
        return Err(CliError::input(format!(
            "{}: {joints} joints; the serial-link firmware is built for {:?} joints \
             (give --elf for one built for {joints}, or --port for a board)",
            mech.name,
            hil_link::UART_JOINTS,
        )));
    }
    let mut plan = hil::plan(&mech, &run).map_err(cli_error)?;
    if let Some(d) = args.duration {
        if !(d.is_finite() && d > 0.0) {
            return Err(CliError::input(format!(
                "--duration {d}: a positive time [s]"
            )));
        }
        let t0 = plan.t_s.first().copied().unwrap_or(0.0);
        let k = plan.t_s.iter().take_while(|t| **t - t0 <= d).count();
        plan.t_s.truncate(k);
        plan.samples.truncate(k);
    }
    if plan.period_s <= 0.0 {
        return Err(CliError::input(format!(
            "{}: fewer than two samples, no period",
            args.run.display()
        )));
    }
    Ok((mech, run, plan))
}

/// Keeps every `k`-th sample of `run` (time, angles, switches).
fn decimate(run: &mut Run, k: usize) {
    fn every<T: Clone>(v: &[T], k: usize) -> Vec<T> {
        v.iter().step_by(k).cloned().collect()
    }
    run.t_s = every(&run.t_s, k);
    for phi in &mut run.phi_deg {
        *phi = every(phi, k);
    }
    for sw in &mut run.latch {
        *sw = every(sw, k);
    }
    run.extra.clear();
}

/// The serial-link ELF for QEMU: `--elf`, or the one built for the
/// mechanism's joint count.
fn uart_elf(args: &HilArgs, mech: &Mechanism) -> Result<PathBuf, CliError> {
    hil_link::find_uart_elf(args.elf.as_deref(), mech.joint_count()).map_err(cli_error)
}

/// Checks every output before the work: writable, and none of the inputs.
fn check_outputs(args: &HilArgs) -> Result<(), CliError> {
    let outputs = [
        ("--out", &args.out),
        ("--plot", &args.plot),
        ("--log", &args.log),
        ("--latency", &args.latency),
    ];
    let inputs: Vec<&std::path::Path> = [&args.run, &args.mechanism]
        .into_iter()
        .chain(&args.elf)
        .map(|p| p.as_path())
        .collect();
    let outputs: Vec<Output> = outputs
        .into_iter()
        .filter_map(|(flag, p)| {
            let p = p.as_deref()?;
            Some(if flag == "--plot" {
                Output::plot(flag, p)
            } else {
                Output::file(flag, p)
            })
        })
        .collect();
    super::check_outputs(&outputs, &inputs)
}

/// Runs `deploywatch hil`.
pub fn run(args: &HilArgs) -> Result<(), CliError> {
    let inject = injection(args)?;
    let (mech, run, plan) = prepare(args)?;
    check_outputs(args)?;
    let endpoint =
        match (args.target, &args.port) {
            (Some(HilTarget::Qemu), Some(_)) => return Err(CliError::input(
                "--port names a serial device: use it with --target serial (or without --target)",
            )),
            (Some(HilTarget::Serial), None) => {
                return Err(CliError::input(
                    "--target serial needs --port DEVICE (e.g. --port /dev/ttyACM0)",
                ))
            }
            (_, Some(port)) => Endpoint::Serial {
                port: port.clone(),
                baud: args.baud,
            },
            (_, None) => Endpoint::Qemu {
                elf: uart_elf(args, &mech)?,
                log: args.log.clone(),
                icount: args.icount,
            },
        };
    let console = Console::new(args.quiet);
    let out = hil::inject(&plan, &inject);
    let keep: Vec<bool> = out.fate.iter().map(|f| f.delivered()).collect();
    console.say(format_args!(
        "{}: {} samples of {} joints at {:.0} Hz (period {:.3} ms), {:.2} s, to {}",
        args.run.display(),
        plan.samples.len(),
        plan.joints,
        1.0 / plan.period_s,
        plan.period_s * 1e3,
        out.at_s.last().copied().unwrap_or(0.0),
        match &args.port {
            Some(p) => format!("{p} at {} baud", args.baud),
            None => "QEMU mps2-an386 over TCP".to_string(),
        }
    ));
    let conn = hil_link::connect(&endpoint).map_err(cli_error)?;
    let settle = Duration::from_secs_f64((50.0 * plan.period_s).max(0.3));
    let got = hil_link::stream(conn, &plan.config, &out, settle).map_err(cli_error)?;
    let reference = hil::reference(&mech, &run, &keep, &got.sheds).map_err(cli_error)?;
    let a = hil::assess(&plan, &out, &got, &reference);
    let problems = verdict(&plan, &out, &got, &a, args.require_deadlines);
    if inject.drop > 0.0 || inject.corrupt > 0.0 || inject.delay > 0.0 {
        against_full(&mech, &run, &plan, &a)?;
    }
    for s in replay::summary(&a.rows) {
        outln!("  {s}");
    }
    write_outputs(args, &mech.name, &a, &console)?;
    if let Some(path) = &args.latency {
        let bad = |e: std::io::Error| CliError::input(format!("--latency {}: {e}", path.display()));
        hil::write_latency_csv(
            std::fs::File::create(path).map_err(bad)?,
            &plan,
            &out,
            &got,
            &a,
        )
        .map_err(bad)?;
        console.say(format_args!("  latency CSV: {}", path.display()));
    }
    match problems {
        Some(p) => Err(CliError::failed(p)),
        None => Ok(()),
    }
}

/// Prints the verdict; the failure, if any.
fn verdict(
    plan: &Plan,
    out: &Outgoing,
    got: &Received,
    a: &Assessment,
    require_deadlines: bool,
) -> Option<String> {
    let mut problems = Vec::new();
    let (dropped, corrupted, delayed) = (
        out.count(Fate::Dropped),
        out.count(Fate::Corrupted),
        out.count(Fate::Delayed),
    );
    let delivered = out.fate.iter().filter(|f| f.delivered()).count();
    outln!(
        "sent: {} sample frames ({dropped} dropped, {corrupted} corrupted, {delayed} delayed on purpose)",
        out.fate.len() - dropped
    );
    match &got.report {
        Some(r) => problems.extend(firmware_counts(r, got, delivered, corrupted)),
        None => problems.push("no link report from the firmware".to_string()),
    }
    outln!(
        "statuses: {} back ({} lost, {} corrupted on the way back); {} of {} bit-identical with \
         the host core on the same input",
        got.statuses.len(),
        a.lost_back,
        a.corrupted_back,
        a.identical,
        delivered
    );
    if a.identical != delivered {
        problems.push(match a.first_difference {
            Some(k) => format!("status {k} differs from the host core's"),
            None => format!("{} of {delivered} statuses as the host core's", a.identical),
        });
    }
    let ms = |x: f64| x * 1e3;
    outln!(
        "latency (sample sent -> status received): median {:.3} ms, p99 {:.3} ms, worst {:.3} ms \
         over {} statuses",
        ms(hil::quantile(&a.latency_s, 0.5)),
        ms(hil::quantile(&a.latency_s, 0.99)),
        ms(a.latency_s.iter().copied().fold(0.0, f64::max)),
        a.latency_s.len()
    );
    outln!(
        "deadline misses (status later than the period, {:.3} ms): {} of {}",
        ms(plan.period_s),
        a.misses,
        a.latency_s.len()
    );
    if require_deadlines && a.misses > 0 {
        problems.push(format!("{} deadline misses", a.misses));
    }
    (!problems.is_empty()).then(|| problems.join("; "))
}

/// Prints the firmware's link report against what the host sent; the
/// problems it shows (counts not the host's, bytes lost, shed frames lost).
fn firmware_counts(
    r: &LinkReport,
    got: &Received,
    delivered: usize,
    corrupted: usize,
) -> Vec<String> {
    let mut problems = Vec::new();
    let exact = r.samples as usize == delivered && r.corrupted as usize == corrupted;
    outln!(
        "firmware: {} samples used, {} corrupted, {} too long, {} bytes overrun: {}",
        r.samples,
        r.corrupted,
        r.too_long,
        r.overrun,
        if exact {
            "counted exactly"
        } else {
            "NOT as sent"
        }
    );
    if !exact || r.too_long > 0 || r.overrun > 0 {
        problems.push(format!(
            "the firmware counted {} samples and {} corrupted frames ({} too long, {} \
             overrun bytes); the host delivered {delivered} and corrupted {corrupted}",
            r.samples, r.corrupted, r.too_long, r.overrun
        ));
    }
    outln!(
        "prediction: slices cut short by a waiting frame after {} of {} samples ({} \
         shed frames back)",
        r.shed,
        r.samples,
        got.sheds.len()
    );
    if r.shed as usize != got.sheds.len() {
        problems.push(format!(
            "the firmware shed slices after {} samples; {} shed frames came back",
            r.shed,
            got.sheds.len()
        ));
    }
    problems
}

/// With frames injected: what the loss did against the whole run on the
/// host (false latches, fault flags the whole run never raises).
fn against_full(mech: &Mechanism, run: &Run, plan: &Plan, a: &Assessment) -> Result<(), CliError> {
    let all = vec![true; plan.samples.len()];
    let full = hil::reference(mech, run, &all, &[]).map_err(cli_error)?;
    let full_rows: Vec<replay::StatusRow> = full
        .iter()
        .map(|f| replay::decode_statuses(f, plan.joints))
        .collect::<Result<Vec<_>, _>>()
        .map_err(cli_error)?
        .into_iter()
        .flatten()
        .collect();
    let (false_latch, extra) = hil::against_full(&full_rows, &a.rows);
    outln!(
        "against the whole run on the host: false latches at joints {:?}; flags it never raises: {}",
        false_latch,
        if extra.is_empty() {
            "none".to_string()
        } else {
            extra
                .iter()
                .map(|(j, f)| format!("joint {j} {f}"))
                .collect::<Vec<_>>()
                .join(", ")
        }
    );
    Ok(())
}

/// Writes the status CSV (`--out`) and the plot (`--plot`).
fn write_outputs(
    args: &HilArgs,
    name: &str,
    a: &Assessment,
    console: &Console,
) -> Result<(), CliError> {
    if let Some(out) = &args.out {
        let bad = |e: std::io::Error| CliError::input(format!("--out {}: {e}", out.display()));
        let file = std::fs::File::create(out).map_err(bad)?;
        replay::write_status_csv(std::io::BufWriter::new(file), &a.rows).map_err(bad)?;
        console.say(format_args!("  status CSV: {}", out.display()));
    }
    if let Some(png) = &args.plot {
        replay::plot(png, name, &a.rows).map_err(|e| CliError::failed(e.to_string()))?;
        console.say(format_args!("  plot: {}", png.display()));
    }
    Ok(())
}
