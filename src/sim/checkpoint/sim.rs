//! The solver's whole state written to and read from a checkpoint blob, item by item.

use super::*;

impl Sim {
    /// The state a step and the run loop's solver read, into `b` (names under `sim.`, `p.`, `w.`).
    pub fn save_state<'a>(&'a self, b: &mut Blob<'a>) {
        let Sim {
            case: _,
            cfg: _,
            plan,
            p,
            w,
            t,
            nstep,
            dt_prev,
            book,
            stab,
            h_init,
            region,
            x_init,
            e_initial,
            index_of_id,
            cmp: _,
            timers,
            dt_first,
            pace,
        } = self;
        b.put_f64("sim.t", &[*t]);
        b.put("sim.nstep", Item::U64(vec![*nstep]));
        b.put_f64("sim.dt_prev", &[*dt_prev]);
        let Book { work_wall, work_penalty, work_gravity, work_floor, work_boundary } = book;
        b.put_f64("sim.book", &[*work_wall, *work_penalty, *work_gravity, *work_floor, *work_boundary]);
        let Stability {
            max_wall_penetration_m,
            left_domain,
            h_ratio_min,
            h_ratio_max,
            min_interface_gap_dx,
            max_neighbours,
            mean_neighbours,
            nan,
        } = stab;
        b.put_f64(
            "sim.stab.f",
            &[
                *max_wall_penetration_m,
                *h_ratio_min,
                *h_ratio_max,
                min_interface_gap_dx.unwrap_or(f64::NAN),
                *mean_neighbours,
            ],
        );
        b.put(
            "sim.stab.n",
            Item::U64(vec![
                *left_domain as u64,
                *max_neighbours as u64,
                u64::from(*nan),
                u64::from(min_interface_gap_dx.is_some()),
            ]),
        );
        b.put_ref("sim.h_init", Ref::F64(h_init));
        b.put_ref("sim.region", Ref::U32(region));
        b.put_ref("sim.x_init", Ref::F64(x_init));
        b.put_f64("sim.e_initial", &[*e_initial]);
        b.put_ref("sim.index_of_id", Ref::U32(index_of_id));
        let names: Vec<&str> = timers.keys().copied().collect();
        b.put_text("sim.timers.names", &names.join("\n"));
        b.put_f64("sim.timers.seconds", &timers.values().copied().collect::<Vec<_>>());
        b.put_f64("sim.dt_first", &[*dt_first]);
        b.put("sim.pace", Item::U64(vec![pace.0]));
        b.put_f64("sim.pace_t", &[pace.1]);
        let stages: Vec<&str> = plan.entries.iter().map(|e| e.stage.name()).collect();
        b.put_text("sim.plan.stages", &stages.join("\n"));
        b.put_f64("sim.plan.seconds", &plan.entries.iter().map(|e| e.seconds).collect::<Vec<_>>());

        save_particles(p, b);

        save_work(w, b);
    }

    /// Puts the state of `b` into this simulation, built from the same case (or, with
    /// `--allow-changed`, a changed one): refused with one line when the checkpoint cannot be
    /// the state of this simulation (another particle count, another plan).
    pub fn restore_state(&mut self, b: &Blob) -> Result<()> {
        // what must agree before anything is replaced
        let sizes = b.u64("p.sizes")?;
        let [dim, nreal, ntotal] = sizes.as_slice() else { return Err(bad("`p.sizes` must hold 3 values")) };
        let (dim, nreal, ntotal) = (usize_of("dim", *dim)?, usize_of("nreal", *nreal)?, usize_of("ntotal", *ntotal)?);
        if dim != self.p.dim || nreal != self.p.nreal {
            return Err(input(format!(
                "the checkpoint holds {nreal} particles in {dim}D; the case makes {} in {}D: it is not this case's state",
                self.p.nreal, self.p.dim
            )));
        }
        let stages: Vec<&str> = self.plan.entries.iter().map(|e| e.stage.name()).collect();
        let saved = b.text("sim.plan.stages")?;
        if saved != stages.join("\n") {
            return Err(input(format!(
                "the checkpoint's step has the stages {}; the case's has {}: it is not this case's state",
                saved.replace('\n', ", "),
                stages.join(", ")
            )));
        }
        let nmat = self.case.materials.len();
        let self_regions = self.case.regions.len();
        let Sim {
            case: _,
            cfg: _,
            plan,
            p,
            w,
            t,
            nstep,
            dt_prev,
            book,
            stab,
            h_init,
            region,
            x_init,
            e_initial,
            index_of_id,
            cmp: _,
            timers,
            dt_first,
            pace,
        } = self;

        restore_particles(p, b, (dim, nreal, ntotal), nmat)?;

        restore_work(w, b, ntotal)?;

        *t = b.scalar("sim.t")?;
        *nstep = b.count("sim.nstep")?;
        *dt_prev = b.scalar("sim.dt_prev")?;
        let bk = b.f64("sim.book")?;
        // a checkpoint written before the boundary particles' book holds 4 values
        let (wall, penalty, gravity, floor, boundary) = match bk.as_slice() {
            [a, b, c, d] => (*a, *b, *c, *d, 0.0),
            [a, b, c, d, e] => (*a, *b, *c, *d, *e),
            _ => return Err(bad("`sim.book` must hold 5 values")),
        };
        *book = Book {
            work_wall: wall,
            work_penalty: penalty,
            work_gravity: gravity,
            work_floor: floor,
            work_boundary: boundary,
        };
        let sf = b.f64("sim.stab.f")?;
        let sn = b.u64("sim.stab.n")?;
        let ([pen, hmin, hmax, gap, mean], [left, maxn, nan, has_gap]) = (sf.as_slice(), sn.as_slice()) else {
            return Err(bad("`sim.stab` must hold 5 reals and 4 counts"));
        };
        *stab = Stability {
            max_wall_penetration_m: *pen,
            left_domain: usize_of("left_domain", *left)?,
            h_ratio_min: *hmin,
            h_ratio_max: *hmax,
            min_interface_gap_dx: (*has_gap != 0).then_some(*gap),
            max_neighbours: usize_of("max_neighbours", *maxn)?,
            mean_neighbours: *mean,
            nan: *nan != 0,
        };
        for (name, a, n) in [("sim.h_init", &mut *h_init, nreal), ("sim.x_init", &mut *x_init, dim * nreal)] {
            let val = b.f64(name)?;
            sized(name, val.len(), n)?;
            *a = val;
        }
        let nregion = self_regions;
        for (name, a, below) in [("sim.region", &mut *region, nregion), ("sim.index_of_id", &mut *index_of_id, nreal)] {
            let val = b.u32(name)?;
            sized(name, val.len(), nreal)?;
            if val.iter().any(|&k| k as usize >= below) {
                return Err(bad(&format!("`{name}` holds an index out of range")));
            }
            *a = val;
        }
        *e_initial = b.scalar("sim.e_initial")?;
        let names = b.text("sim.timers.names")?;
        let secs = b.f64("sim.timers.seconds")?;
        timers.clear();
        for (n, s) in names.split('\n').filter(|n| !n.is_empty()).zip(secs) {
            // the solver's timers are named by string literals; a resumed run names them anew
            // (a handful of bytes, once per resume)
            timers.insert(Box::leak(n.to_string().into_boxed_str()), s);
        }
        *dt_first = b.scalar("sim.dt_first")?;
        *pace = (b.count("sim.pace")?, b.scalar("sim.pace_t")?);
        let secs = b.f64("sim.plan.seconds")?;
        for (e, s) in plan.entries.iter_mut().zip(secs) {
            e.seconds = s;
        }
        Ok(())
    }
}

/// Refused unless the checkpoint's item `name` holds `want` values.
fn sized(name: &str, got: usize, want: usize) -> Result<()> {
    if got == want { Ok(()) } else { Err(bad(&format!("`{name}` holds {got} values, not {want}"))) }
}

/// The particles' arrays into `b` (names under `p.`).
fn save_particles<'a>(p: &'a Particles, b: &mut Blob<'a>) {
    let Particles {
        dim,
        nreal,
        ntotal,
        x,
        v,
        rho,
        p: pr,
        c,
        e,
        h,
        mass,
        mat,
        id,
        tau,
        tlight,
        burn,
        h0,
        rho0,
        alpha,
        sigma0,
        rho_max,
        bnd,
    } = p;
    b.put("p.sizes", Item::U64(vec![*dim as u64, *nreal as u64, *ntotal as u64]));
    for (name, a) in [
        ("p.x", x),
        ("p.v", v),
        ("p.rho", rho),
        ("p.p", pr),
        ("p.c", c),
        ("p.e", e),
        ("p.h", h),
        ("p.mass", mass),
        ("p.tau", tau),
        ("p.tlight", tlight),
        ("p.burn", burn),
        ("p.h0", h0),
        ("p.rho0", rho0),
        ("p.alpha", alpha),
        ("p.sigma0", sigma0),
        ("p.rho_max", rho_max),
    ] {
        b.put_ref(name, Ref::F64(a));
    }
    b.put_ref("p.mat", Ref::I32(mat));
    b.put_ref("p.bnd", Ref::I32(bnd));
    b.put_ref("p.id", Ref::I64(id));
}

/// The work arrays a step carries over into `b` (names under `w.`).
fn save_work<'a>(w: &'a Work, b: &mut Blob<'a>) {
    let Work {
        pairs,
        w: ww,
        dwdx,
        w0,
        drho,
        acc,
        dde,
        dv,
        de,
        eps,
        rot,
        dtau,
        av,
        dhdt,
        rho_min,
        e_min,
        v_min,
        tau_min,
        gsrc,
        gseg,
        dt_cfl,
        rinv,
        pmass,
        mumax,
        efloor,
        divv: _, // the viscosity switch's workspace, recomputed before every use
    } = w;
    b.put_ref("w.pairs.i", Ref::I32(&pairs.i));
    b.put_ref("w.pairs.j", Ref::I32(&pairs.j));
    for (name, a) in [
        ("w.w", ww),
        ("w.dwdx", dwdx),
        ("w.w0", w0),
        ("w.drho", drho),
        ("w.acc", acc),
        ("w.dde", dde),
        ("w.dv", dv),
        ("w.de", de),
        ("w.eps", eps),
        ("w.rot", rot),
        ("w.dtau", dtau),
        ("w.av", av),
        ("w.dhdt", dhdt),
        ("w.rho_min", rho_min),
        ("w.e_min", e_min),
        ("w.v_min", v_min),
        ("w.tau_min", tau_min),
        ("w.dt_cfl", dt_cfl),
        ("w.rinv", rinv),
        ("w.pmass", pmass),
        ("w.mumax", mumax),
        ("w.efloor", efloor),
    ] {
        b.put_ref(name, Ref::F64(a));
    }
    b.put_ref("w.gsrc", Ref::I32(gsrc));
    b.put_ref("w.gseg", Ref::I32(gseg));
}

/// The particles' arrays from `b`, checked against the sizes (dim, nreal, ntotal) and the
/// case's `nmat` materials.
fn restore_particles(
    p: &mut Particles,
    b: &Blob,
    (dim, nreal, ntotal): (usize, usize, usize),
    nmat: usize,
) -> Result<()> {
    let Particles {
        dim: _,
        nreal: _,
        ntotal: p_ntotal,
        x,
        v,
        rho,
        p: pr,
        c,
        e,
        h,
        mass,
        mat,
        id,
        tau,
        tlight,
        burn,
        h0,
        rho0,
        alpha,
        sigma0,
        rho_max,
        bnd,
    } = p;
    let new_mat = b.i32("p.mat")?;
    sized("p.mat", new_mat.len(), ntotal)?;
    if let Some(m) = new_mat.iter().find(|&&m| m < 0 || m as usize >= nmat) {
        return Err(input(format!("the checkpoint has a particle of material {m}; the case has {nmat} materials")));
    }
    let new_id = b.i64("p.id")?;
    sized("p.id", new_id.len(), id.len())?;
    if new_id.iter().any(|&i| i < 0 || i as usize >= nreal) {
        return Err(bad("a particle id out of range"));
    }
    for (name, a, n) in [
        ("p.x", &mut *x, dim * ntotal),
        ("p.v", &mut *v, dim * ntotal),
        ("p.rho", &mut *rho, ntotal),
        ("p.p", &mut *pr, ntotal),
        ("p.c", &mut *c, ntotal),
        ("p.e", &mut *e, ntotal),
        ("p.h", &mut *h, ntotal),
        ("p.mass", &mut *mass, ntotal),
    ] {
        let val = b.f64(name)?;
        sized(name, val.len(), n)?;
        *a = val;
    }
    // allocated by the stages that use them (register): their sizes are the case's
    for (name, a) in [
        ("p.tlight", &mut *tlight),
        ("p.burn", &mut *burn),
        ("p.h0", &mut *h0),
        ("p.rho0", &mut *rho0),
        ("p.sigma0", &mut *sigma0),
    ] {
        let val = b.f64(name)?;
        sized(name, val.len(), a.len())?;
        *a = val;
    }
    // the compaction history: absent from a checkpoint of a binary without it, which is only
    // right for a case without a compaction EOS
    let new_rmax = b.f64("p.rho_max").or_else(|e| if rho_max.is_empty() { Ok(vec![]) } else { Err(e) })?;
    sized("p.rho_max", new_rmax.len(), rho_max.len())?;
    *rho_max = new_rmax;
    // the boundary-particle kinds: absent from a checkpoint of a binary without them, which is
    // only right for a case without boundary particles
    let new_bnd = b.i32("p.bnd").or_else(|e| if bnd.is_empty() { Ok(vec![]) } else { Err(e) })?;
    sized("p.bnd", new_bnd.len(), bnd.len())?;
    if new_bnd.iter().any(|&k| !(0..=2).contains(&k)) {
        return Err(bad("a boundary-particle kind out of range"));
    }
    *bnd = new_bnd;
    let new_tau = b.f64("p.tau")?;
    sized("p.tau", new_tau.len(), if tau.is_empty() { 0 } else { crate::modules::param::NSTR * ntotal })?;
    *tau = new_tau;
    let new_alpha = b.f64("p.alpha")?;
    sized("p.alpha", new_alpha.len(), if alpha.is_empty() { 0 } else { ntotal })?;
    *alpha = new_alpha;
    *mat = new_mat;
    *id = new_id;
    *p_ntotal = ntotal;
    Ok(())
}

/// The work arrays from `b`, checked against the `ntotal` particles.
fn restore_work(w: &mut Work, b: &Blob, ntotal: usize) -> Result<()> {
    let Work {
        pairs,
        w: ww,
        dwdx,
        w0,
        drho,
        acc,
        dde,
        dv,
        de,
        eps,
        rot,
        dtau,
        av,
        dhdt,
        rho_min,
        e_min,
        v_min,
        tau_min,
        gsrc,
        gseg,
        dt_cfl,
        rinv,
        pmass,
        mumax,
        efloor,
        divv: _, // the viscosity switch's workspace, recomputed before every use
    } = w;
    let (pi, pj) = (b.i32("w.pairs.i")?, b.i32("w.pairs.j")?);
    sized("w.pairs.j", pj.len(), pi.len())?;
    if pi.iter().chain(&pj).any(|&k| k < 0 || k as usize >= ntotal) {
        return Err(bad("a pair of particles out of range"));
    }
    *pairs = crate::modules::nnps::PairList::new(pi, pj);
    for (name, a) in [
        ("w.w", ww),
        ("w.dwdx", dwdx),
        ("w.w0", w0),
        ("w.drho", drho),
        ("w.acc", acc),
        ("w.dde", dde),
        ("w.dv", dv),
        ("w.de", de),
        ("w.eps", eps),
        ("w.rot", rot),
        ("w.dtau", dtau),
        ("w.av", av),
        ("w.dhdt", dhdt),
        ("w.rho_min", rho_min),
        ("w.e_min", e_min),
        ("w.v_min", v_min),
        ("w.tau_min", tau_min),
        ("w.dt_cfl", dt_cfl),
        ("w.rinv", rinv),
        ("w.pmass", pmass),
        ("w.mumax", mumax),
        ("w.efloor", efloor),
    ] {
        *a = b.f64(name)?;
    }
    *gsrc = b.i32("w.gsrc")?;
    *gseg = b.i32("w.gseg")?;
    Ok(())
}
