//! What every module's interface shares: the named constants of the legacy core (from
//! `fortran/include/blastsph_legacy.h`, as `sph_param.f90` defines them), the material table and
//! the wall segments.

#[allow(non_upper_case_globals, non_camel_case_types, non_snake_case, dead_code)]
mod consts {
    include!(concat!(env!("OUT_DIR"), "/param.rs"));
}

pub use consts::{
    SPH_EOS_IDEAL_GAS, SPH_EOS_JWL, SPH_EOS_NONE, SPH_EOS_SOIL, SPH_EOS_WATER, SPH_MP_ALPHA_PHI, SPH_MP_COHESION,
    SPH_MP_E1, SPH_MP_ECHEM, SPH_MP_ETA_CJ, SPH_MP_PMIN, SPH_MP_RHO0, SPH_MP_SHEAR, SPH_MP_UNR_C, SPH_MP_UNR_GAMMA,
    SPH_MP_UNR_S, SPH_NPAR, SPH_NSTR, SPH_SKF_CUBIC, SPH_SKF_GAUSS, SPH_SKF_QUINTIC, SPH_SKF_WENDLAND,
};

include!(concat!(env!("OUT_DIR"), "/table.rs"));

/// Rows of the material table.
pub const NPAR: usize = SPH_NPAR as usize;
/// Stored deviatoric stress components: xx, yy, zz, xy, xz, yz.
pub const NSTR: usize = SPH_NSTR as usize;

/// The material table passed to every routine that dispatches per material.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MatTable {
    /// `SPH_EOS_*` code per material.
    pub mtype: Vec<i32>,
    /// `mpar(SPH_NPAR, nmat)`, rows as `SPH_MP_*` (1-based rows: row r is `mpar[r-1 + NPAR*m]`).
    pub mpar: Vec<f64>,
    /// Penalty group per material: pairs in different groups feel the penalty force.
    pub group: Vec<i32>,
}

impl MatTable {
    pub fn nmat(&self) -> usize {
        self.mtype.len()
    }
    /// The value of row `row` (a 1-based `SPH_MP_*` index) for material `m`.
    pub fn par(&self, m: usize, row: u32) -> f64 {
        self.mpar[(row as usize - 1) + NPAR * m]
    }
    /// The column of material `m`.
    pub fn column(&self, m: usize) -> &[f64] {
        &self.mpar[NPAR * m..NPAR * (m + 1)]
    }
    /// True when some material is a JWL explosive.
    pub fn has_jwl(&self) -> bool {
        self.mtype.contains(&(SPH_EOS_JWL as i32))
    }
}

/// Values per wall in `Segments::seg`: 3·dim in 1D and 2D (start, end, inward unit normal), 12 in
/// 3D (a corner, the two edge vectors, the inward unit normal): the Fortran's
/// `3*dim + 3*(dim/3)`. The normal is always the last `dim` values.
pub fn seg_len(dim: usize) -> usize {
    3 * dim + 3 * (dim / 3)
}

/// Wall segments as the boundary routines take them: `seg(nsv, nseg)` ([`seg_len`]) and the
/// end-node flag of each (1D, 2D: the end node is the wall's; 3D: the mask of the edges it owns,
/// 1 the far edge along the first edge vector, 2 along the second, 4 and 8 the near ones).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Segments {
    pub seg: Vec<f64>,
    pub endnode: Vec<i32>,
}

impl Segments {
    pub fn len(&self) -> usize {
        self.endnode.len()
    }
    pub fn is_empty(&self) -> bool {
        self.endnode.is_empty()
    }
    /// Segment `s` ([`seg_len`] values).
    pub fn get(&self, dim: usize, s: usize) -> &[f64] {
        let l = seg_len(dim);
        &self.seg[l * s..l * (s + 1)]
    }
}
