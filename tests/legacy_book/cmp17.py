import subprocess, sys, re
h5, ref, step = sys.argv[1], sys.argv[2], sys.argv[3]
def ds(name, fmt="%.17g"):
    out = subprocess.run(["h5dump", "-d", f"/Step#{step}/{name}", "-m", fmt, "-y", "-w", "0", h5], capture_output=True, text=True).stdout
    body = out.split("DATA {",1)[1].split("}",1)[0]
    return [float(v) for v in re.split(r"[,\s]+", body.strip()) if v]
ids = [int(v) for v in ds("id", "%d")]
x = ds("x"); v = ds("vx"); n = len(ids)
dimx = len(x)//n
got = {"x": x[0::dimx], "vx": v[0::dimx], "mass": ds("mass"), "rho": ds("rho"), "p": ds("p"), "u": ds("e"), "hsml": ds("h")}
rows = {}
for l in open(ref):
    f = l.split(); rows[int(f[0])-1] = [float(t) for t in f[1:]]
cols = ["x","vx","mass","rho","p","u","hsml"]
worst = {}
for i,k in enumerate(ids):
    r = rows[k]
    for c,col in enumerate(cols):
        d = abs(got[col][i]-r[c]); worst[col] = max(worst.get(col,0), d)
print("particles", n, "max|diff| per field:", {k: float('%.3g'%v) for k,v in worst.items()})
