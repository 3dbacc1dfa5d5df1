//! Every case file at two sizes (levels 0 and 2 of its first `[[sweep]]`, first space and
//! scheme): a full run (prepare + all steps, no output). Criterion's throughput is in dof·steps,
//! so it reports the time per dof and step; divide the time by the printed step count for the
//! time per step.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use dyncontact::cases::{self, Overrides};
use std::hint::black_box;
use std::path::Path;

fn cases_at_two_sizes(c: &mut Criterion) {
    for file in [
        "cases/bar1d.toml",
        "cases/spring_mass.toml",
        "cases/hertz2d.toml",
    ] {
        let path = Path::new(file);
        let base = cases::load(path, &Overrides::default()).expect("valid case");
        let sweep = &base.sweeps()[0];
        let levels = sweep.refinements(false).expect("valid sweep");
        let mut g = c.benchmark_group(format!("case/{}", base.kind()));
        g.sample_size(10);
        for level in [0, 2.min(levels.len() - 1)] {
            let o = sweep.overrides(&sweep.spaces[0], &sweep.schemes[0], levels[level]);
            let case = cases::load(path, &o).expect("valid case");
            let probe = dyncontact::study::run::run(case.as_ref()).expect("run");
            let (dofs, steps) = (probe.summary.dofs, probe.summary.steps);
            println!(
                "case/{} level {level}: {dofs} dofs × {steps} steps",
                base.kind()
            );
            g.throughput(Throughput::Elements((dofs * steps) as u64));
            g.bench_with_input(
                BenchmarkId::new(format!("{dofs}dofs_{steps}steps"), level),
                &level,
                |b, _| {
                    b.iter(|| black_box(dyncontact::study::run::run(case.as_ref()).expect("run")))
                },
            );
        }
        g.finish();
    }
}

criterion_group!(benches, cases_at_two_sizes);
criterion_main!(benches);
