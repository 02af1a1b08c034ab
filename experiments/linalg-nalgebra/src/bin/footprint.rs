//! Links the linalg functions of the implementations the features select,
//! called once on opaque inputs, and nothing else: the flash of an
//! implementation is this binary's flash less that of the build with no
//! feature (scripts/linalg-eval.sh). Never run; only linked and sized.
#![no_std]
#![no_main]

#[cfg(any(feature = "impl-core", feature = "impl-nalgebra"))]
use core::hint::black_box;
use cortex_m_rt::entry;

#[entry]
fn main() -> ! {
    #[cfg(feature = "impl-core")]
    {
        use linalg_nalgebra::core_impl as c;
        black_box(c::solve2(
            black_box(&[[0.0; 2]; 2]),
            black_box(&[0.0; 2]),
            black_box(&[false; 2]),
        ));
        black_box(c::solve3(
            black_box(&[[0.0; 3]; 3]),
            black_box(&[0.0; 3]),
            black_box(&[false; 3]),
        ));
        black_box(c::inertias2(
            black_box(&[[0.0; 2]; 2]),
            black_box(&[false; 2]),
        ));
        black_box(c::inertias3(
            black_box(&[[0.0; 3]; 3]),
            black_box(&[false; 3]),
        ));
        black_box(c::inertia2(
            black_box(&[[0.0; 2]; 2]),
            black_box(&[false; 2]),
            black_box(0),
        ));
        black_box(c::inertia3(
            black_box(&[[0.0; 3]; 3]),
            black_box(&[false; 3]),
            black_box(0),
        ));
        black_box(c::mat_vec2(black_box(&[[0.0; 2]; 2]), black_box(&[0.0; 2])));
        black_box(c::mat_vec3(black_box(&[[0.0; 3]; 3]), black_box(&[0.0; 3])));
    }
    #[cfg(feature = "impl-nalgebra")]
    {
        use linalg_nalgebra::nalgebra_impl as n;
        black_box(n::solve2(
            black_box(&[[0.0; 2]; 2]),
            black_box(&[0.0; 2]),
            black_box(&[false; 2]),
        ));
        black_box(n::solve3(
            black_box(&[[0.0; 3]; 3]),
            black_box(&[0.0; 3]),
            black_box(&[false; 3]),
        ));
        black_box(n::inertias2(
            black_box(&[[0.0; 2]; 2]),
            black_box(&[false; 2]),
        ));
        black_box(n::inertias3(
            black_box(&[[0.0; 3]; 3]),
            black_box(&[false; 3]),
        ));
        black_box(n::inertia2(
            black_box(&[[0.0; 2]; 2]),
            black_box(&[false; 2]),
            black_box(0),
        ));
        black_box(n::inertia3(
            black_box(&[[0.0; 3]; 3]),
            black_box(&[false; 3]),
            black_box(0),
        ));
        black_box(n::mat_vec2(black_box(&[[0.0; 2]; 2]), black_box(&[0.0; 2])));
        black_box(n::mat_vec3(black_box(&[[0.0; 3]; 3]), black_box(&[0.0; 3])));
    }
    loop {
        cortex_m::asm::wfi();
    }
}

/// No formatting: a panic path costs the same in every build.
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    cortex_m::asm::udf()
}
