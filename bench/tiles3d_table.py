# SPDX-License-Identifier: Apache-2.0
"""Prints the figures of docs/benchmarks/tiles3d.md for the run folders given (bench/tiles3d.sh)."""
import json
import os
import sys


def sizes(run):
    tiles3d = today = parents = 0
    for d, _, files in os.walk(run):
        for f in files:
            p = os.path.join(d, f)
            n = os.path.getsize(p)
            parts = p.split(os.sep)
            if "3dtiles" in parts:
                tiles3d += n
                if "lod" in parts:
                    parents += n
            elif f.endswith((".ply", ".obj", ".mtl", ".png")) and f != "dynamic_points.ply":
                today += n
    return tiles3d, today, parents


def main():
    for run in sys.argv[1:]:
        r = json.load(open(os.path.join(run, "report.json")))
        st = r["stages"]["export.3dtiles"]
        t3, today, parents = sizes(run)
        total = r["timings"]["total_s"]
        if "tiles" in r:
            writer = sum(t["stages"].get("export.3dtiles", {}).get("wall_time_s", 0) for t in r["tiles"].values())
        else:
            writer = st.get("wall_time_s", 0)
        writer += st.get("finish_run_s", 0)
        # CPU: the leaf writer's thread CPU per tile, the parents' process CPU (finishRun runs
        # alone), against the run's process CPU: does not grow with the machine's load.
        if "tiles" in r:
            writer_cpu = sum(t["stages"].get("export.3dtiles", {}).get("cpu_time_s", 0) for t in r["tiles"].values())
        else:
            writer_cpu = st.get("cpu_time_s", 0)
        writer_cpu += st.get("finish_run_cpu_s", 0)
        cpu = r["timings"].get("cpu_s", 0)
        faces = st.get("leaf_faces", 0)
        leaf_bytes = st.get("leaf_glb_bytes", 0)
        print(f"== {run}")
        print(f"3D Tiles bytes {t3} (parents {parents}), PLY+OBJ+MTL+PNG bytes {today}, ratio {t3 / today:.3f}")
        print(f"leaf faces {faces}, leaf GLB bytes {leaf_bytes}, bytes/face {leaf_bytes / max(1, faces):.1f}")
        print(f"run {total:.1f} s, writer {writer:.2f} s = {100 * writer / total:.1f} %; "
              f"CPU: run {cpu:.1f} s, writer {writer_cpu:.2f} s = {100 * writer_cpu / max(cpu, 1e-9):.1f} %")
        lod = st.get("lod_timings_s", {})
        if lod:
            parts = ", ".join(f"{k} {v:.2f}" for k, v in lod.items() if not isinstance(v, list))
            print(f"  LOD (finish_run_s {st.get('finish_run_s', 0):.2f} s): {parts} s; per level {lod.get('levels', [])}")
        for lv in st.get("levels", []):
            extra = ""
            if lv["level"] > 0:
                extra = f", texel {lv.get('texel_m', 0):.3f} m, {lv.get('texels', 0)} texels, {lv.get('charts', 0)} charts"
            print(f"  level {lv['level']}: {lv['tiles']} tiles, {lv['faces']} faces, "
                  f"geometricError {lv['geometric_error_m']:.3f} m{extra}")


main()
