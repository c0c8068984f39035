//! The book's `virt_part` mapped as a set-up step: called once after the set-up, its virtual
//! particles become boundary particles of the manifest's `virtual` kind.

mod legacy_kit;
use legacy_kit::*;

/// A virt_part in the book's dialect: three particles beyond each end of the fixture's tube,
/// at rest, with the state of the end particle next to them and itype = -1.
const VIRT_PART: &str = "      subroutine virt_part(itimestep, ntotal, nvirt, hsml, mass, x,
     &                     vx, rho, u, p, itype)
      implicit none
      include 'param.inc'
      integer itimestep, ntotal, nvirt, itype(maxn)
      double precision hsml(maxn), mass(maxn), x(dim,maxn),
     &        vx(dim,maxn), rho(maxn), u(maxn), p(maxn)
      integer i, k, j, e
      double precision dl, dr

      dl = 0.6/80./4.
      dr = 0.6/80.
      nvirt = 0
      do 20 k = 1, 2
        if (k .eq. 1) then
          e = 1
        else
          e = ntotal
        endif
        do 10 i = 1, 3
          nvirt = nvirt + 1
          j = ntotal + nvirt
          if (k .eq. 1) then
            x(1,j) = x(1,e) - dl*i
          else
            x(1,j) = x(1,e) + dr*i
          endif
          vx(1,j) = 0.
          mass(j) = mass(e)
          hsml(j) = hsml(e)
          rho(j) = rho(e)
          u(j) = u(e)
          p(j) = p(e)
          itype(j) = -1
   10   continue
   20 continue

      end
";

const ENTRY: &str = "
[[routine]]
name = \"virt_part\"
module = \"boundary\"
args = [\"itimestep\", \"ntotal\", \"nvirt\", \"hsml\", \"mass\", \"x\", \"vx\", \"rho\", \"u\", \"p\", \"itype\"]
";

/// The fixture with `virt_part.f`, its manifest entry carrying `extra` keys.
fn with_virt(name: &str, extra: &str) -> PathBuf {
    let d = variant(name, |m| format!("{m}{ENTRY}{extra}"));
    std::fs::write(d.join("virt_part.f"), VIRT_PART).unwrap();
    d
}

#[test]
fn check_says_what_virt_part_made() {
    for (kind, extra) in [("held", ""), ("integrated", "virtual = \"integrated\"\n")] {
        let d = with_virt(&format!("virt_{kind}"), extra);
        build(&d.join("legacy.toml"), &d.join("build")).expect("the variant builds");
        let o = blastsph(&["check", "shock_tube", "--legacy", d.join("build").to_str().unwrap()]);
        let (so, se) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
        assert_eq!(o.status.code(), Some(0), "{so}{se}");
        let line =
            so.lines().find(|l| l.contains("virt_part")).unwrap_or_else(|| panic!("check names virt_part: {so}"));
        assert!(line.contains(&format!("made 6 boundary particles, {kind}")), "{line}");
        assert!(!so.contains("virt_part is not run"), "{so}");
    }
}

#[test]
fn virtual_is_refused_on_another_routine_and_of_another_kind() {
    let d = variant("virt_elsewhere", |m| {
        m.replacen("module = \"setup\"\n", "module = \"setup\"\nvirtual = \"held\"\n", 1)
    });
    refused(&d, &["virtual", "virt_part"]);
    let d = with_virt("virt_bad_kind", "virtual = \"frozen\"\n");
    refused(&d, &["virtual", "frozen"]);
}

#[test]
fn dual_compares_every_mapped_routine_at_zero_ulp_with_the_virtual_particles() {
    let d = with_virt("virt_dual", "");
    let b = d.join("build");
    build(&d.join("legacy.toml"), &b).expect("the variant builds");
    let out = d.join("dual");
    let args = ["dual", "shock_tube", "--legacy", b.to_str().unwrap(), "--compat", "liu-book"];
    let so = blastsph_ok(&[&args[..], &["--set", "time.end_s=0.2", "--out", out.to_str().unwrap()]].concat(), 0);
    assert!(so.contains("40 steps compared; every compared stage within tolerance"), "{so}");
    let (_, rows) = report_rows(&out.join("dual_report.json"));
    let legacy: Vec<_> =
        rows.iter().filter(|x| x["stage"].as_str().is_some_and(|s| s.starts_with("legacy."))).collect();
    assert!(legacy.len() >= 10, "{rows:?}");
    for x in legacy {
        assert_eq!((x["max_ulp"].as_u64(), x["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{x}");
    }
    // the 400 real particles and the 6 virtual ones, at each of the 40 steps
    assert_eq!(row(&rows, "legacy.sum_density", "rho")["compared"].as_u64(), Some(406 * 40));
}

/// The manifest's entry of the fixture's output routine (the real particles' final state).
const OUTPUT: &str = "
[[routine]]
name = \"output\"
module = \"output\"
args = [\"x\", \"vx\", \"mass\", \"rho\", \"p\", \"u\", \"c\", \"itype\", \"hsml\", \"ntotal\"]
";

/// The variant in `d` built into `d/build`, its program run for 40 steps (final state in the
/// scratch folder `NAME_run`), and `run --legacy --compat liu-book` of the shock tube to 0.2 s
/// (into `NAME_legacy`): the build, the run folder, the program's final state and the run's last
/// frame. The run's
/// ordinary particles must be the program's final state bit for bit ([`assert_real_particles_as`]).
fn program_and_legacy_run(d: &Path, name: &str) -> (PathBuf, PathBuf, Vec<Vec<f64>>, blastsph::output::Frame) {
    let b = d.join("build");
    build(&d.join("legacy.toml"), &b).expect("the variant builds");
    let rows = program_rows_of(&b, &format!("{name}_run"), 40);
    assert_eq!(rows.len(), 400, "the program writes its real particles");
    let out = scratch(&format!("{name}_legacy"));
    let args = ["run", "shock_tube", "--legacy", b.to_str().unwrap(), "--compat", "liu-book"];
    blastsph_ok(&[&args[..], &["--set", "time.end_s=0.2", "--out", out.to_str().unwrap(), "--quiet"]].concat(), 0);
    let f = blastsph::output::read_frames(&out.join("particles.h5")).expect("particles.h5").pop().unwrap();
    assert!((f.time - 0.2).abs() < 1e-6, "t = {}", f.time);
    assert_real_particles_as(&f, &rows);
    (b, out, rows, f)
}

/// The ordinary particles of frame `f` are the program's final state `rows` (columns: number,
/// type, x, vx, mass, rho, p, u, hsml), bit for bit, all 400 of them.
fn assert_real_particles_as(f: &blastsph::output::Frame, rows: &[Vec<f64>]) {
    let mut seen = 0;
    for i in (0..f.x.len()).filter(|&i| f.bnd[i] == 0) {
        let r = &rows[f.id[i] as usize];
        let got = [f.x[i], f.vx[i], f.mass[i], f.rho[i], f.p[i], f.e[i], f.h[i]];
        let want = [r[2], r[3], r[4], r[5], r[6], r[7], r[8]];
        assert_eq!(got, want, "particle {} (x, vx, mass, rho, p, u, hsml)", f.id[i] + 1);
        seen += 1;
    }
    assert_eq!(seen, 400);
}

/// A virt_part whose particles do not depend on the real ones: 16 beyond the left end at the
/// left spacing and 4 beyond the right end at the right one (a kernel's reach each), at rest, in
/// the state of their side at the start.
const VIRT_FIXED: &str = "      subroutine virt_part(itimestep, ntotal, nvirt, hsml, mass, x,
     &                     vx, rho, u, p, itype)
      implicit none
      include 'param.inc'
      integer itimestep, ntotal, nvirt, itype(maxn)
      double precision hsml(maxn), mass(maxn), x(dim,maxn),
     &        vx(dim,maxn), rho(maxn), u(maxn), p(maxn)
      integer i, j
      double precision dxr

      dxr = 0.6/80.
      nvirt = 0
      do 10 i = 1, 20
        nvirt = nvirt + 1
        j = ntotal + nvirt
        if (i .le. 16) then
          x(1,j) = -0.6 - dxr/4.*i
          rho(j) = 1.
          u(j) = 2.5
          p(j) = 1.
        else
          x(1,j) = 0.6 + dxr*(i - 16)
          rho(j) = 0.25
          u(j) = 1.795
          p(j) = 0.1795
        endif
        vx(1,j) = 0.
        mass(j) = 0.75/400.
        hsml(j) = 0.015
        itype(j) = -1
   10 continue

      end
";

/// The fixture's own program calling virt_part at every step, as the book does, against
/// `run --legacy` with the manifest's held virtual particles made once: the real particles end
/// bit for bit in the program's final state. The virtual particles' state does not depend on
/// the real ones, so making them once and holding them is the same as making them every step.
#[test]
fn held_virtual_particles_made_once_end_as_the_program_that_makes_them_every_step() {
    let d = with_virt("virt_program", OUTPUT);
    std::fs::write(d.join("virt_part.f"), VIRT_FIXED).unwrap();
    let ss = d.join("single_step.f");
    let text = std::fs::read_to_string(&ss).unwrap();
    let call =
        "      call virt_part(itimestep, ntotal, nvirt, hsml, mass, x,\n     &               vx, rho, u, p, itype)\n";
    let new = text.replacen("      nvirt = 0\n", call, 1);
    assert_ne!(new, text, "single_step.f sets nvirt = 0");
    std::fs::write(&ss, new).unwrap();
    let (b, out, rows, f) = program_and_legacy_run(&d, "virt_program");
    assert_eq!(f.bnd.iter().filter(|&&k| k == 2).count(), 20, "20 held particles");
    // the program's left end, pushed by nothing without them, stays near its place
    assert!((rows[0][2] + 0.6).abs() < 0.01, "left end at {}", rows[0][2]);

    // `legacy compare` hands the output routine the book's ntotal (the 400 real particles, the
    // 20 boundary ones after them): its file is the program's, at every digit written
    let prog = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("migration/virt_program_run");
    let cmp = scratch("virt_program_compare");
    let (r, b, p, c) = (out.to_str().unwrap(), b.to_str().unwrap(), prog.to_str().unwrap(), cmp.to_str().unwrap());
    let so = blastsph_ok(&["legacy", "compare", r, "--legacy", b, "--program-out", p, "--out", c], 0);
    assert!(so.contains("equal at the"), "{so}");
}

/// Edits of the fixture's `time_integration.f` and `single_step.f` into a code that makes its
/// virtual particles once, at the first step, and integrates their u, ρ and v over
/// `ntotal + nvirt` (x over `ntotal`), while its rate sum covers the real particles only, as the
/// book's `single_step` does (a dam-break code of that kind exists).
fn integrating_program(d: &Path) {
    let edit = |file: &str, pairs: &[(&str, &str)]| {
        let p = d.join(file);
        let mut text = std::fs::read_to_string(&p).unwrap();
        for (a, b) in pairs {
            assert!(text.contains(a), "{file}: {a}");
            text = text.replacen(a, b, 1);
        }
        std::fs::write(&p, text).unwrap();
    };
    let loop_all = |label: &str| format!("          do {label} i = 1, ntotal + nvirt\n");
    edit(
        "time_integration.f",
        &[
            (
                "      integer i, d, itimestep, nstart, current_ts\n",
                "      integer i, d, itimestep, nstart, current_ts, nvirt\n",
            ),
            (
                "      do 10 i = 1, ntotal\n",
                "      nvirt = 0\n      do 10 i = 1, maxn\n        du(i) = 0.\n        do 8 d = 1, dim\n          dvx(d,i) = 0.\n    8   continue\n",
            ),
            ("          do 30 i = 1, ntotal\n", &loop_all("30")),
            (
                "              vx(d,i) = vx(d,i) + (dt/2.)*dvx(d,i)\n",
                "              if (i .le. ntotal) vx(d,i) = vx(d,i) + (dt/2.)*dvx(d,i)\n",
            ),
            ("     &                   itype, av)\n", "     &                   itype, av, nvirt)\n"),
            ("          do 50 i = 1, ntotal\n", &loop_all("50")),
            ("          do 70 i = 1, ntotal\n", &loop_all("70")),
            (
                "              x(d,i) = x(d,i) + dt*vx(d,i)\n   40",
                "              if (i .le. ntotal) x(d,i) = x(d,i) + dt*vx(d,i)\n   40",
            ),
            (
                "              x(d,i) = x(d,i) + dt*vx(d,i)\n   60",
                "              if (i .le. ntotal) x(d,i) = x(d,i) + dt*vx(d,i)\n   60",
            ),
        ],
    );
    edit(
        "single_step.f",
        &[
            (
                "     &                       drho, itype, av)\n",
                "     &                       drho, itype, av, nvirt)\n",
            ),
            (
                "      nvirt = 0\n",
                "      if (itimestep .eq. 1) call virt_part(itimestep, ntotal,\n     &    nvirt, hsml, mass, x, vx, rho, u, p, itype)\n",
            ),
        ],
    );
}

/// The code of [`integrating_program`] against `run --legacy` with `virtual = "integrated"`
/// under the book's profile: the real particles end bit for bit in the program's final state
/// (the profile's rate sum leaves a boundary particle dv = 0 and int_force's du).
#[test]
fn integrated_virtual_particles_end_as_a_program_that_integrates_them() {
    let d = with_virt("virt_integrating", "virtual = \"integrated\"\n");
    std::fs::write(d.join("virt_part.f"), VIRT_FIXED).unwrap();
    integrating_program(&d);
    let (_, _, _, f) = program_and_legacy_run(&d, "virt_integrating");
    assert_eq!(f.bnd.iter().filter(|&&k| k == 1).count(), 20, "20 integrated particles");
    // the virtual particles' u moved (int_force's du), their x and v did not
    let virt: Vec<usize> = (0..f.x.len()).filter(|&i| f.bnd[i] == 1).collect();
    assert!(virt.iter().any(|&i| f.e[i] != 2.5 && f.e[i] != 1.795), "no virtual u changed");
    assert!(virt.iter().all(|&i| f.vx[i] == 0.0), "a virtual particle moved its v");
}

/// `blastsph legacy host CASE --legacy BUILD --compat liu-book --out OUT`, the program's input
/// `40` then `0` on stdin: (status, stdout, stderr) and the report.
fn host_run(case: &Path, b: &Path, out: &Path) -> (Option<i32>, String, serde_json::Value) {
    let (c, b, o) = (case.to_str().unwrap(), b.to_str().unwrap(), out.to_str().unwrap());
    let o = blastsph_40_steps(&["legacy", "host", c, "--legacy", b, "--compat", "liu-book", "--out", o]);
    let text = format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    let r = std::fs::read_to_string(out.join("host_report.json"))
        .map_or(serde_json::Value::Null, |t| serde_json::from_str(&t).unwrap());
    (o.status.code(), text, r)
}

/// The row of `field` of routine `name` in a host report.
fn host_row<'a>(r: &'a serde_json::Value, name: &str, field: &str) -> &'a serde_json::Value {
    let rows = r["routines"][name]["rows"].as_array().unwrap_or_else(|| panic!("{name}: {r}"));
    rows.iter().find(|x| x["field"] == field).unwrap_or_else(|| panic!("{name} {field}: {r}"))
}

/// The fixture's program calling virt_part at every step, with the book's averaged velocity, in
/// host mode. av_vel is given the real particles' ntotal, and its pairs reach the 20 virtual
/// particles. It is compared over the 400 particles it is given, at 0 ULP at each of its 40
/// calls. The rows past them hold its pair sums without ε: they are not compared.
#[test]
fn host_mode_compares_av_vel_over_the_particles_it_is_given() {
    let d = with_virt("virt_host_xsph", "");
    std::fs::write(d.join("virt_part.f"), VIRT_FIXED).unwrap();
    for (file, a, b) in [
        (
            "single_step.f",
            "      nvirt = 0\n",
            "      call virt_part(itimestep, ntotal, nvirt, hsml, mass,\n     &               x, vx, rho, u, p, itype)\n",
        ),
        ("param.inc", "parameter (average_velocity  = .false.)", "parameter (average_velocity  = .true.)"),
    ] {
        let p = d.join(file);
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.contains(a), "{file}: {a}");
        std::fs::write(&p, text.replacen(a, b, 1)).unwrap();
    }
    let b = d.join("build");
    build(&d.join("legacy.toml"), &b).expect("the variant builds");
    let (code, text, r) = host_run(&xsph_case(&d), &b, &scratch("virt_host_xsph_run"));
    assert_eq!(code, Some(0), "{text}");
    let av = host_row(&r, "av_vel", "av");
    assert_eq!(r["routines"]["av_vel"]["compared_calls"], 40, "{r}");
    assert_eq!(av["compared"].as_u64(), Some(400 * 40), "{av}");
    assert_eq!((av["max_ulp"].as_u64(), av["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{av}");
}

/// The fixture's program calling virt_part and the repulsion `ext_force` at every step, in host
/// mode with the case's `[boundary] repulsion` at the routine's r0 and D (single-precision
/// literals, as the book writes them; the item `literals` rounds the case's). The program's particles
/// of negative itype are boundary particles for the twin, so its push is compared: 0 ULP at
/// each of the 40 calls.
#[test]
fn host_mode_takes_a_negative_itype_for_a_boundary_particle() {
    let d = with_virt("virt_host_push", &ENTRY.replace("virt_part", "ext_force").replace(
        "[\"itimestep\", \"ntotal\", \"nvirt\", \"hsml\", \"mass\", \"x\", \"vx\", \"rho\", \"u\", \"p\", \"itype\"]",
        "[\"ntotal\", \"mass\", \"x\", \"niac\", \"pair_i\", \"pair_j\", \"itype\", \"hsml\", \"dvxdt\"]",
    ));
    std::fs::write(d.join("virt_part.f"), VIRT_FIXED).unwrap();
    // the repulsion with r0 = 2.5e-3 m: the first of VIRT_FIXED's particles beyond the left end,
    // 1.875e-3 m from it, pushes it
    std::fs::write(d.join("ext_force.f"), ext_force_f(false, "2.5e-3", "1.e-2")).unwrap();
    let call = "      call ext_force(ntotal + nvirt, mass, x, niac, pair_i, pair_j,\n     &               itype, hsml, exdvxdt)\n";
    let p = d.join("single_step.f");
    let text = std::fs::read_to_string(&p).unwrap();
    let (a, at) = ("      nvirt = 0\n", "      if (visc_artificial) call art_visc");
    assert!(text.contains(a) && text.contains(at));
    let virt =
        "      call virt_part(itimestep, ntotal, nvirt, hsml, mass,\n     &               x, vx, rho, u, p, itype)\n";
    std::fs::write(&p, text.replacen(a, virt, 1).replacen(at, &format!("{call}{at}"), 1)).unwrap();
    let b = d.join("build");
    build(&d.join("legacy.toml"), &b).expect("the variant builds");
    let case = d.join("shock_tube_push.toml");
    let text = std::fs::read_to_string(root().join("cases/shock_tube.toml")).unwrap();
    std::fs::write(&case, format!("{text}\n[boundary]\nrepulsion = {{ r0_m = 2.5e-3, d_m2s2 = 1e-2 }}\n")).unwrap();
    let (code, text, r) = host_run(&case, &b, &scratch("virt_host_push_run"));
    assert_eq!(code, Some(0), "{text}");
    assert_eq!(r["routines"]["ext_force"]["compared_calls"], 40, "{r}");
    let acc = host_row(&r, "ext_force", "acc");
    assert_eq!((acc["max_ulp"].as_u64(), acc["out_of_tolerance"].as_u64()), (Some(0), Some(0)), "{acc}");
}
