import sys, time, pickle, math, json
sys.path.insert(0, "/work/wt-estim3/benchmarks")
import numpy as np
from sensor_chain_bench import ROWS, SOURCES, FORCE_NOISE, DEPTH_NOISE, RATE
from mudforce.motions.sensor_chain import SensorChain, apply
from mudforce.estimation.calibration.dataset import Trial
from mudforce.estimation.calibration import identify_water_content
from mudforce.errors import InputError
import argparse
p = argparse.ArgumentParser()
p.add_argument("cache"); p.add_argument("--seed", type=int, default=0)
p.add_argument("--rows", default="all"); p.add_argument("--out", default="res.json")
p.add_argument("--max", type=int, default=99)
a = p.parse_args()
clean = pickle.load(open(a.cache, "rb"))
rows = range(len(ROWS)) if a.rows == "all" else [int(x) for x in a.rows.split(",")]
res = []
t_all = time.perf_counter()
for (kind, index), recs in sorted(clean.items()):
    if index >= a.max: continue
    for source, w, foot, t, z, f in recs:
        bias = float(np.random.default_rng([a.seed, 2, index, SOURCES.index(source)]).uniform(-1.0, 1.0))
        for r in rows:
            name, kset, corruption, _ = ROWS[r]
            fields = {"force_noise": FORCE_NOISE, "depth_noise": DEPTH_NOISE, "force_bias": bias, "rate": RATE, **corruption}
            cseed = int(np.random.default_rng([a.seed, 3, index, SOURCES.index(source), r]).integers(0, 2**32 - 1))
            tt, zz, ff = apply(t, z, f, SensorChain(**fields), cseed)
            t0 = time.perf_counter()
            try:
                x = identify_water_content(Trial(f"{source}{index}", w, tt, zz, ff), foot)
            except InputError as e:
                res.append(dict(row=r, source=source, index=index, w=w, refused=str(e))); continue
            d = x.to_dict(); d.pop("warnings")
            d.update(row=r, source=source, index=index, w=w, flagged=bool(x.warnings), nwarn=len(x.warnings),
                     covered=x.interval[0] <= w <= x.interval[1], err=(x.water_content - w) * 100,
                     secs=time.perf_counter() - t0, extra={k: v for k, v in getattr(x, "_debug", {}).items()})
            d["wrong"] = (not d["covered"]) and not d["flagged"]
            res.append(d)
            print(f"{name:28s} {source:11s} {index} W {w*100:5.2f} est {x.water_content*100:5.2f} [{x.interval[0]*100:5.2f},{x.interval[1]*100:5.2f}] "
                  f"ratio {x.misfit_ratio:5.2f} disc {x.discretisation:5.2f} rmse {x.rmse:5.2f} {'FLAG' if x.warnings else '    '} {'WRONG' if d['wrong'] else ''} {d['secs']:.1f}s", flush=True)
json.dump(res, open(a.out, "w"), default=float)
print("total", time.perf_counter() - t_all)
