//! One Dormand–Prince 5(4) step on a state of run-time size: the rig's
//! state (chain, trolleys, bars, dissipated work) has no compile-time
//! length, unlike the chain's [`crate::simulate::ode`].

/// The Butcher tableau of Dormand–Prince 5(4) (Hairer, Nørsett & Wanner,
/// *Solving ODEs I*, Table 5.2).
const A: [[f64; 6]; 6] = [
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];

/// The fifth-order weights (the last row of [`A`]) minus the fourth-order
/// ones: the error estimate's weights.
const E: [f64; 7] = [
    35.0 / 384.0 - 5179.0 / 57600.0,
    0.0,
    500.0 / 1113.0 - 7571.0 / 16695.0,
    125.0 / 192.0 - 393.0 / 640.0,
    -2187.0 / 6784.0 + 92097.0 / 339200.0,
    11.0 / 84.0 - 187.0 / 2100.0,
    -1.0 / 40.0,
];

/// One step of size `h` from `y` with `f(y)`: the fifth-order solution and
/// the RMS of the error estimate scaled by `atol + rtol |y|`; `None` when
/// the right-hand side fails (a singular mass matrix).
pub fn step(
    f: &mut dyn FnMut(&[f64]) -> Option<Vec<f64>>,
    y: &[f64],
    h: f64,
    rtol: f64,
    atol: f64,
) -> Option<(Vec<f64>, f64)> {
    let n = y.len();
    let mut k: Vec<Vec<f64>> = Vec::with_capacity(7);
    k.push(f(y)?);
    let mut yi = vec![0.0; n];
    for row in A {
        for i in 0..n {
            let mut acc = 0.0;
            for (s, a) in row.iter().enumerate().take(k.len()) {
                acc += a * k[s][i];
            }
            yi[i] = y[i] + h * acc;
        }
        k.push(f(&yi)?);
    }
    // The fifth-order solution is the last stage's argument (FSAL).
    let mut err = 0.0;
    for i in 0..n {
        let e: f64 = E.iter().zip(&k).map(|(w, ks)| w * ks[i]).sum::<f64>() * h;
        let scale = atol + rtol * y[i].abs().max(yi[i].abs());
        err += (e / scale).powi(2);
    }
    Some((yi, (err / n as f64).sqrt()))
}
