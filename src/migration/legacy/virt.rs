//! The book's `virt_part` as a set-up step: called once after the set-up (the user's `input`,
//! or blastsph's own particles), with `itimestep = 1`. The `nvirt` particles it appends after
//! the `ntotal` real ones become boundary particles of the manifest's kind (`virtual = "held"`
//! or `"integrated"`), each of the material whose code is `-itype`.

use super::super::bind::Buf;
use super::Legacy;
use crate::case::Case;
use crate::error::{Result, input};
use crate::setup::Initial;
use crate::state::Particles;

impl Legacy {
    /// The mapped `virt_part` routine, if any.
    fn virt_routine(&self) -> Option<&super::super::builder::RoutineInfo> {
        self.lib.info().routines.iter().find(|r| r.virtual_kind.is_some())
    }

    /// `made` with the boundary particles of the mapped `virt_part` appended; `made` as it is
    /// where none is mapped.
    pub(super) fn virt_part(&self, case: &Case, mut made: Initial) -> Result<Initial> {
        let Some(r) = self.virt_routine() else { return Ok(made) };
        let kind = r.virtual_kind.as_deref().unwrap_or("held");
        let (dim, maxn) = (case.dim, self.lib.info().maxn);
        let n = made.mass.len();
        self.check_capacity(n)?;
        let p = Particles {
            dim,
            nreal: n,
            ntotal: n,
            x: made.x.clone(),
            v: made.v.clone(),
            rho: made.rho.clone(),
            p: vec![0.0; n],
            c: vec![0.0; n],
            e: made.e.clone(),
            h: made.h.clone(),
            mass: made.mass.clone(),
            mat: made.mat.clone(),
            ..Default::default()
        };
        let mut bufs = self.set_up_bufs(r, &p, 1);
        self.call_quiet(&r.name, &r.bindings, &mut bufs)?;
        let get = |name: &str| r.bindings.iter().position(|b| b.name == name).map(|k| &bufs[k]);
        let int = |name: &str| match get(name) {
            Some(Buf::I(v)) => Ok(v.clone()),
            _ => Err(input(format!("legacy {}: a virt_part routine must take {name}", r.name))),
        };
        let nv = int("nvirt")?[0];
        if nv < 0 || n + nv as usize > maxn {
            return Err(input(format!("legacy {}: returned nvirt = {nv} ({n} real particles, maxn = {maxn})", r.name)));
        }
        let (nv, itype) = (nv as usize, int("itype")?);
        let real = |name: &str, w: usize| -> Result<Vec<f64>> {
            match get(name) {
                Some(Buf::R(v)) => Ok(v[w * n..w * (n + nv)].to_vec()),
                _ => Err(input(format!("legacy {}: a virt_part routine must give {name}", r.name))),
            }
        };
        let (x, v, rho, e, h, mass) =
            (real("x", dim)?, real("vx", dim)?, real("rho", 1)?, real("u", 1)?, real("hsml", 1)?, real("mass", 1)?);
        // the real particles' kinds, from the regions, before the boundary particles'
        if made.bnd.is_empty() {
            made.bnd = crate::setup::boundary_kinds(case, &made.region);
        }
        let code = if kind == "integrated" { 1 } else { 2 };
        for (i, &t) in itype[n..n + nv].iter().enumerate() {
            let m = self.itype.iter().position(|&k| k == -t).ok_or_else(|| {
                input(format!(
                    "legacy {}: virtual particle {} has itype {t}, but no material of the case has code {} (codes: {:?})",
                    r.name,
                    n + i + 1,
                    -t,
                    self.itype
                ))
            })?;
            let name = &case.materials[m].name;
            let g = case.regions.iter().position(|rg| &rg.material == name).unwrap_or(0);
            made.mat.push(m as i32);
            made.region.push(g as u32);
            if let Some(c) = made.counts.get_mut(g) {
                *c += 1;
            }
            made.bnd.push(code);
        }
        made.x.extend(x);
        made.v.extend(v);
        made.rho.extend(rho);
        made.e.extend(e);
        made.h.extend(h);
        made.mass.extend(mass);
        self.shared().virt_made = Some((nv, kind.to_string()));
        Ok(made)
    }
}
