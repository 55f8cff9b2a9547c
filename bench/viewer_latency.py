#!/usr/bin/env python3
"""How fast raycast view shows an edit: the time from saving the scene file to having the new
first image (1 sample per pixel, what the page asks for first), for the course's seven scenes (or
the project's own testcases/ when ../shared is absent) and for a 69k-triangle mesh.

    python3 bench/viewer_latency.py [path/to/raycast]      (default build-bench/raycast)

For each scene: start `raycast view SCENE`, then five times: rewrite the file (a comment changes),
poll /status every 5 ms until its version grows, GET /image?spp=1; report the median and the
largest time, and the parts: until the reload shows in /status, and the render. Prints a Markdown
table. Uses only the Python standard library.
"""
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def status_version(url):
    text = urllib.request.urlopen(url + "status", timeout=60).read().decode()
    return int(re.search(r'"version": (\d+)', text).group(1))


def measure(raycast, folder, scene, runs=5):
    server = subprocess.Popen([raycast, "view", scene, "--port", "0", "-q"], cwd=folder, stdout=subprocess.PIPE,
                              text=True)
    try:
        url = server.stdout.readline().strip()
        path = os.path.join(folder, scene)
        with open(path) as f:
            original = f.read()
        urllib.request.urlopen(url + "image?spp=1", timeout=120).read()  # warm up
        totals, reloads, renders = [], [], []
        for run in range(runs):
            version = status_version(url)
            time.sleep(0.3)  # the watcher's clock starts fresh, as after a person's edit
            start = time.perf_counter()
            with open(path, "w") as f:
                f.write(original + "\n# edit %d\n" % run)
            while status_version(url) <= version:
                time.sleep(0.005)
            reloaded = time.perf_counter()
            urllib.request.urlopen(url + "image?spp=1", timeout=120).read()
            done = time.perf_counter()
            totals.append(done - start)
            reloads.append(reloaded - start)
            renders.append(done - reloaded)
        with open(path, "w") as f:
            f.write(original)
        return totals, reloads, renders
    finally:
        server.terminate()
        server.wait()


def main():
    raycast = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build-bench", "raycast"))
    meshgen = os.path.join(os.path.dirname(raycast), "raycast_meshgen")
    work = tempfile.mkdtemp(prefix="raycast-latency-")
    shared = os.path.join(os.path.dirname(ROOT), "shared", "course")
    source = shared if os.path.isdir(shared) else ROOT
    shutil.copytree(os.path.join(source, "testcases"), os.path.join(work, "testcases"))
    shutil.copytree(os.path.join(source, "mesh"), os.path.join(work, "mesh"))
    scenes = sorted(os.path.join("testcases", name) for name in os.listdir(os.path.join(work, "testcases")))
    # A 69k-triangle mesh (the size of the Stanford bunny, which is not available offline here).
    subprocess.run([meshgen, "bumpy-sphere", "69451", os.path.join(work, "mesh", "bumpy_69k.obj"), "--seed", "1"],
                   check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(work, "testcases", "bumpy_69k.txt"), "w") as f:
        f.write("PerspectiveCamera { center 0 0 5.3 direction 0 0 -1 up 0 1 0 angle 30 width 800 height 800 }\n"
                "Lights { numLights 1 DirectionalLight { direction -0.5 -0.6 -1 color 0.9 0.9 0.9 } }\n"
                "Background { color 0.1 0.1 0.15 }\n"
                "Materials { numMaterials 1 PhongMaterial { diffuseColor 0.7 0.6 0.5 specularColor 0.3 0.3 0.3 "
                "shininess 20 } }\n"
                "Group { numObjects 1 MaterialIndex 0 TriangleMesh { obj_file mesh/bumpy_69k.obj } }\n")
    scenes.append(os.path.join("testcases", "bumpy_69k.txt"))
    print("raycast view: from saving the scene to the new first image (1 sample per pixel), %s, load %s" %
          (time.strftime("%Y-%m-%d"), " ".join(open("/proc/loadavg").read().split()[:3])))
    print()
    print("| scene | median ms | largest ms | until /status shows the reload (median ms) | render + PNG (median ms) |")
    print("|---|---:|---:|---:|---:|")
    for scene in scenes:
        totals, reloads, renders = measure(raycast, work, scene)
        print("| %s | %.0f | %.0f | %.0f | %.0f |" % (os.path.basename(scene), 1000 * statistics.median(totals),
                                                   1000 * max(totals), 1000 * statistics.median(reloads),
                                                   1000 * statistics.median(renders)))
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
