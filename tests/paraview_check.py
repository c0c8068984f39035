"""Opens a run directory's particles.xmf with ParaView's own Python (pvpython) as a user's
script would (OpenDataFile), and checks what ParaView sees against what the run wrote.

    pvpython tests/paraview_check.py RUN_DIR N_STEPS N_PARTICLES WITH_STRESS(0|1)

Prints one line per check; exits 1 at the first failure. Run by `cargo test --release --test
paraview -- --ignored` (README)."""
import sys

from paraview import servermanager as sm
from paraview.simple import OpenDataFile, XDMFReader


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def fetch(reader, t):
    reader.UpdatePipeline(t)
    d = sm.Fetch(reader)
    if d.IsA("vtkMultiBlockDataSet"):
        d = d.GetBlock(0)
    return d


def main():
    run_dir, nsteps, npart, stress = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4] == "1"
    path = run_dir + "/particles.xmf"
    readers = [("OpenDataFile", OpenDataFile(path)), ("XDMFReader", XDMFReader(FileNames=[path]))]
    for label, r in readers:
        if r is None:
            fail(label + ": no reader for " + path)
        times = list(r.TimestepValues)
        if len(times) != nsteps:
            fail("%s (%s): %d time steps, the run wrote %d" % (label, r.GetXMLName(), len(times), nsteps))
        for t in times:
            d = fetch(r, t)
            if d.GetNumberOfPoints() != npart:
                fail("%s at t = %g: %d points, want %d" % (label, t, d.GetNumberOfPoints(), npart))
            if d.GetNumberOfCells() != npart:
                fail("%s at t = %g: %d cells, want one vertex per particle" % (label, t, d.GetNumberOfCells()))
            pd = d.GetPointData()
            v = pd.GetArray("velocity")
            if v is None or v.GetNumberOfComponents() != 3:
                fail("%s at t = %g: no 3-component velocity" % (label, t))
            s = pd.GetArray("stress")
            if stress and (s is None or s.GetNumberOfComponents() != 9):
                fail("%s at t = %g: no 3x3 stress tensor" % (label, t))
            for name in ("rho", "p", "mat", "id"):
                if pd.GetArray(name) is None:
                    fail("%s at t = %g: no array %s" % (label, t, name))
        d = fetch(r, times[-1])
        vr = d.GetPointData().GetArray("velocity").GetRange(-1)
        print("ok %s (%s): %d steps, %d points, |velocity| up to %.4g m/s%s" % (
            label, r.GetXMLName(), len(times), d.GetNumberOfPoints(), vr[1],
            ", stress tensor" if stress else ""))
    print("paraview: all checks passed")


main()
