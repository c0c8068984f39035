/*
 * blastsph_legacy.h -- C prototypes of every bind(C) routine of the legacy Fortran core.
 *
 * This header is the contract: build.rs hands it to bindgen, and each prototype must match its
 * Fortran interface (fortran/src/sph_<module>.f90).
 *
 * Conventions at the C boundary
 *  - scalars passed with `value` are plain int / double; scalar outputs are pointers;
 *  - arrays are column-major in the Fortran layout: x(dim, n) is x[d + dim*i];
 *  - particle and pair indices are 0-based (the Fortran adds 1);
 *  - `const` marks intent(in); arrays of size max(k,1) may be a 1-element dummy when k = 0;
 *  - the stress is stored as tau(6, n): xx, yy, zz, xy, xz, yz;
 *  - materials: mtype[nmat] (SPH_EOS_*), mpar(SPH_NPAR, nmat) with 1-based rows SPH_MP_*.
 */
#ifndef BLASTSPH_LEGACY_H
#define BLASTSPH_LEGACY_H

#define SPH_NPAR 16
#define SPH_NSTR 6
#define SPH_MP_RHO0 1
#define SPH_MP_E1 2
#define SPH_MP_PMIN 8
#define SPH_MP_SHEAR 9
#define SPH_MP_ALPHA_PHI 10
#define SPH_MP_COHESION 11
#define SPH_MP_UNR_C 12
#define SPH_MP_UNR_S 13
#define SPH_MP_UNR_GAMMA 14
#define SPH_MP_ECHEM 15
#define SPH_MP_ETA_CJ 16

#define SPH_EOS_NONE 0
#define SPH_EOS_IDEAL_GAS 1
#define SPH_EOS_JWL 2
#define SPH_EOS_WATER 3
#define SPH_EOS_SOIL 4

#define SPH_SKF_CUBIC 1
#define SPH_SKF_GAUSS 2
#define SPH_SKF_QUINTIC 3
#define SPH_SKF_WENDLAND 4

/* kernel (sph_kernel.f90) */
void sph_kernel_pairs(int dim, int ntotal, int npair, int skf, double gscale,
                      const int *pair_i, const int *pair_j, const double *x, const double *h,
                      double *w, double *dwdx);
void sph_kernel_self(int dim, int n, int skf, const double *h, double *w0);
void sph_kernel_point(int dim, int skf, const double *dx, double h, double *w, double *dwdx);

/* nnps (sph_nnps.f90) */
void sph_nnps_direct(int dim, int nreal, int ntotal, const double *x, const double *h,
                     double kappa, int maxpair, int *npair, int *pair_i, int *pair_j);
void sph_nnps_cell(int dim, int nreal, int ntotal, const double *x, const double *h,
                   double kappa, int maxpair, int *npair, int *pair_i, int *pair_j);

/* density (sph_density.f90) */
void sph_density_sum(int ntotal, int npair, const int *pair_i, const int *pair_j,
                     const double *w, const double *w0, const double *mass, double *rho);
void sph_density_rate(int dim, int ntotal, int npair, const int *pair_i, const int *pair_j,
                      const double *dwdx, const double *mass, const double *v, double *drho);
void sph_density_rate_vol(int dim, int ntotal, int npair, const int *pair_i, const int *pair_j,
                          const double *dwdx, const double *mass, const double *rho,
                          const double *v, double *drho);

/* eos (sph_eos.f90) */
void sph_eos_eval(int n, int nmat, const int *mtype, const double *mpar, const int *mat,
                  int nburn, const double *burn, const double *rho, const double *e, double *p,
                  double *c);

/* force (sph_force.f90) */
void sph_force_internal(int dim, int ntotal, int npair, const int *pair_i, const int *pair_j,
                        const double *dwdx, const double *mass, const double *rho,
                        const double *p, const double *v, int ntau, const double *tau,
                        int eform, int nrinv, const double *rinv, double *dvdt,
                        double *dedt);

/* viscosity (sph_viscosity.f90) */
void sph_viscosity_monaghan(int dim, int ntotal, int npair, const int *pair_i,
                            const int *pair_j, const double *dwdx, const double *x,
                            const double *v, const double *h, const double *rho,
                            const double *c, const double *mass, double alpha, double beta,
                            double etq, int nalpha, const double *alpv, double amax,
                            int nrinv, const double *rinv, double *dvdt, double *dedt,
                            double *mumax);
void sph_viscosity_switch(int dim, int ntotal, int n, int npair, const int *pair_i,
                          const int *pair_j, const double *dwdx, const double *mass,
                          const double *rho, const double *v, const double *h, const double *c,
                          double amin, double amax, double ell, double dt, double *alpv,
                          double *dv);

/* conductivity (sph_conductivity.f90) */
void sph_conductivity_price(int dim, int ntotal, int npair, const int *pair_i, const int *pair_j,
                            const double *dwdx, const double *x, const double *v,
                            const double *rho, const double *p, const double *e,
                            const double *mass, double alpha, int signal, int nrinv, const double *rinv,
                            double *dedt);

/* strength (sph_strength.f90) */
void sph_strength_rates(int dim, int ntotal, int n, int npair, const int *pair_i,
                        const int *pair_j, const double *dwdx, const double *mass,
                        const double *rho, const double *v, const int *mat, int nmat,
                        const double *mpar, const double *tau, int nr, const double *rinv,
                        double *eps, double *rot, double *dtau, double *dedt);
void sph_strength_yield(int n, const int *mat, int nmat, const double *mpar, const double *p,
                        double *tau);

/* penalty (sph_penalty.f90) */
void sph_penalty_force(int dim, int ntotal, int npair, const int *pair_i, const int *pair_j,
                       const double *x, const double *h, const double *mass, const int *mat,
                       int nmat, const int *group, double pbar, int n1, int n2, double *dvdt);

/* boundary (sph_boundary.f90); seg(nsv, nseg), nsv = 3*dim + 3*(dim/3): 1D, 2D start, end,
 * inward unit normal; 3D corner, edge vectors u and v, inward unit normal. gseg(2 + dim/3, ng). */
void sph_boundary_wall_force(int dim, int n, const double *x, int nseg, const double *seg,
                             const int *endnode, double spacing, double r0, double dcoef,
                             int n1, int n2, double *dvdt);
void sph_boundary_mirror_make(int dim, int n, const double *x, const double *h, double kappa,
                              int nseg, const double *seg, int maxg, int *ng, int *gsrc,
                              int *gseg);
void sph_boundary_mirror_fill(int dim, int ntotal, int n, int ng, const int *gsrc,
                              const int *gseg, int nseg, const double *seg, int noslip,
                              double *x, double *v, double *rho, double *p, double *c,
                              double *e, double *h, double *mass, int *mat, int ntau,
                              double *tau);
void sph_boundary_mirror_copy(int ntotal, int n, int ng, const int *gsrc, double *f);

/* geometry (sph_geometry.f90): the axisymmetric (RZ) ring quantities and hoop terms */
void sph_geometry_ring(int dim, int ntotal, const double *x, const double *h, const double *mass,
                       double *rinv, double *pmass);
void sph_geometry_hoop(int dim, int ntotal, int n, const double *rho, const double *rinv,
                       const double *tau, double *dvdt);
void sph_geometry_continuity(int dim, int ntotal, int n, const double *v, const double *rho,
                             const double *rinv, double *drho);

/* smoothing (sph_smoothing.f90) */
void sph_smoothing_density(int dim, int n, const double *rho, const double *h0,
                           const double *rho0, int nr, const double *rinv, double hmax,
                           double *h);
void sph_smoothing_rate(int dim, int n, const double *rho, const double *h, const double *drho,
                        double *dhdt);
void sph_smoothing_advance(int n, double dt, double theta, double hmax, const double *dhdt,
                           double *h);

/* xsph (sph_xsph.f90) */
void sph_xsph_average(int dim, int ntotal, int npair, const int *pair_i, const int *pair_j,
                      const double *w, const double *mass, const double *rho, const double *v,
                      double eps, double *av);

/* detonation (sph_detonation.f90) */
void sph_detonation_light(int dim, int n, const double *x, const int *mat, int nmat,
                          const int *mtype, const double *mpar, const double *xdet, double sf,
                          double *tlight);
void sph_detonation_burn(int n, double t, const int *mat, int nmat, const double *mpar,
                         const double *tlight, const double *h, const double *rho, double width,
                         double *burn);

/* integrator (sph_integrator.f90) */
void sph_integrator_sum_rates(int dim, int n, int lda, int nterm, const double *acc,
                              const double *grav, double *dv);
void sph_integrator_predict(int dim, int n, int ntau, double dt_prev, int cont, double *rho,
                            const double *drho, double *e, const double *de, double *v,
                            const double *dv, double *tau, const double *dtau, double *rho_min,
                            double *e_min, double *v_min, double *tau_min);
void sph_integrator_advance(int dim, int n, int ntau, int first, double dt_prev, double dt,
                            int cont, double *rho, const double *drho, double *e,
                            const double *de, double *v, const double *dv, double *tau,
                            const double *dtau, const double *rho_min, const double *e_min,
                            const double *v_min, const double *tau_min, int nav,
                            const double *av, double *x);
void sph_integrator_cfl(int dim, int n, double cfl, const double *h, const double *c,
                        const double *v, const double *dv, int nmu, double kv,
                        const double *mumax, double *dt);
void sph_integrator_efloor(int n, const double *mass, double *e, double *added);

#endif
