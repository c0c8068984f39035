#!/bin/bash
# The check of docs/migration.md A.7 on a copy of the genuine book code (not in this repository).
#   tests/legacy_book/check.sh BOOK [BLASTSPH]
# BOOK holds src/ (the book's files and its param.inc) and main/sph.f, fetched as README.md says.
# Writes into BOOK/: the manifest and stubs of this folder, ref*/ (the book's own sequence at 17
# digits), build*/, dual*/, run*/, ledger/; prints every table. Needs gfortran, h5dump, python3.
set -euo pipefail
BOOK=$(realpath "$1"); B=${2:-$(dirname "$0")/../../target/release/blastsph}; B=$(realpath "$B")
HERE=$(realpath "$(dirname "$0")")
cd "$BOOK"; rm -rf build dual dual_plain run ledger ref40 prog v_*; cp -r "$HERE"/stubs "$HERE"/legacy.toml "$HERE"/shock_tube_book.toml "$HERE"/cmp17.py .
FL="-O2 -ffp-contract=off -std=legacy -finit-local-zero"
# ref DIR STEPS: the book's own sequence (stubs/driver17.f: sph.f's calls) from DIR/src
ref() { mkdir -p "$1/ref$2/TEST/data"; (cd "$1/ref$2" && gfortran $FL -I../src ../src/*.f ../stubs/driver17.f \
  ../stubs/tree_search.f -o drv17 > build.log 2>&1 && echo "$2" | ./drv17 > out.txt); }
# the book's program itself (sph.f), with gfortran timers in place of the dfport ones
mkdir -p prog/TEST/data && (cd prog && gfortran $FL -I../src ../src/*.f ../main/sph.f ../stubs/tree_search.f \
  ../stubs/time_gfortran.f90 -o sph > build.log 2>&1 && printf "40\n0\n" | ./sph > out.txt)
ref . 40; cmp prog/TEST/data/f_state.dat ref40/TEST/data/f_state.dat && echo "driver17 = sph.f (f_state.dat identical)"
$B legacy build legacy.toml --out build
$B check shock_tube_book.toml --legacy build --compat liu-book | sed -n '/^legacy routines/,$p'
$B dual shock_tube_book.toml --legacy build --compat liu-book --out dual | grep -E "^legacy|steps compared"
$B run shock_tube_book.toml --legacy build --compat liu-book --out run --quiet --force
python3 cmp17.py run/particles.h5 ref40/final17.dat 10
$B dual shock_tube_book.toml --legacy build --out dual_plain | grep -E "^legacy|steps compared" || true
$B legacy ledger shock_tube_book.toml --legacy build --out ledger | sed -n '/^run /,$p'
# param.inc's other switches: a copy each, its compat item
variant() {  # NAME SED COMPAT [MANIFEST-SED] [CASE-SED] [STEPS]
  local V="$BOOK/v_$1"; rm -rf "$V"; mkdir -p "$V"; cp -r src main stubs legacy.toml shock_tube_book.toml cmp17.py "$V"/
  sed -i "$2" "$V/src/param.inc"; [ -n "${4:-}" ] && sed -i "$4" "$V/legacy.toml"; [ -n "${5:-}" ] && sed -i "$5" "$V/shock_tube_book.toml"
  local N=${6:-40}; ref "$V" $N; echo "== $1 (--compat $3, $N steps)"
  (cd "$V" && $B legacy build legacy.toml --out build > /dev/null \
    && $B dual shock_tube_book.toml --legacy build --compat "$3" --out dual | grep -E "^legacy|steps compared" \
    && $B run shock_tube_book.toml --legacy build --compat "$3" --set time.end_s=$(python3 -c "print($N*0.005)") --out run --quiet --force \
    && python3 cmp17.py run/particles.h5 ref$N/final17.dat $((N/4)))
}
variant pa1 's/parameter(pa_sph = 2)/parameter(pa_sph = 1)/' liu-book,pa_sph1
variant nor 's/nor_density  = .false./nor_density  = .true./' liu-book,nor_density
variant link 's/parameter(nnps = 1 )/parameter(nnps = 2 )/' liu-book,global_h 's/name = "direct_find"/name = "link_list"/'
variant con 's/summation_density  = .true./summation_density  = .false./' liu-book \
  '/^name = "sum_density"/,/^args/{s/name = "sum_density"/name = "con_density"/;s/^args = .*/args = ["ntotal", "mass", "niac", "pair_i", "pair_j", "dwdx", "vx", "itype", "x", "rho", "drhodt"]/}' \
  's/^density = "summation"/density = "continuity"\ncontinuity_form = "mass"/' 12
variant sle2 's/parameter(sle = 0)/parameter(sle = 2)/' liu-book,h_upgrade \
  '$a\\n[[routine]]\nname = "h_upgrade"\nmodule = "smoothing"\nargs = ["dt", "ntotal", "mass", "vx", "rho", "niac", "pair_i", "pair_j", "dwdx", "hsml"]' \
  's/^smoothing = "constant"/smoothing = "rate"/' 12
