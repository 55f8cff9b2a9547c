#!/usr/bin/env python3
"""Whether `raycast view` counts every save of the scene as one version, on a loaded machine.

    python3 tools/viewer_save_stress.py [path/to/raycast] [SAVES]   (default build/raycast, 250)

Starts `raycast view` on a small scene, then, with busy loops on every core (two per core) and
this script at the lowest priority (nice 19, so that its saves lose the processor in the middle),
saves the file SAVES times, as Python's open(path, "w") does (truncate, write, close), each time
waiting until /status shows the next version (30 s at most) and then 250 ms more. A save that is
read while the file is still empty shows as two versions. Prints each save that is not one version
(two, or none) and a count; exits 1 if there was one. Took 135 s for 250 saves on the two-core Intel Xeon.

Before bb207f7 the viewer loaded a change it found before the kernel had queued its event: 58
double versions in 250 saves on the two-core Intel Xeon; none after. That is the race behind the
rare `ViewerInChromium` failures under `ctest -j2`, which this reproduces in minutes instead of
dozens of CI runs. Uses only the Python standard library.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

SCENE = """PerspectiveCamera {
    center 0 0 8
    direction 0 0 -1
    up 0 1 0
    angle 40
    width 160
    height 120
}
Lights {
    numLights 1
    DirectionalLight {
        direction -0.3 -1 -0.6
        color 0.9 0.9 0.9
    }
}
Background {
    color 0.25 0.35 0.55
    ambientLight 0.1 0.1 0.1
}
Materials {
    numMaterials 1
    PhongMaterial {
        diffuseColor 0.8 0.3 0.2
    }
}
Group {
    numObjects 1
    MaterialIndex 0
    Sphere {
        center 0 0 0
        radius 0.7
    }
}
"""

# A typo, a new colour, the original: every save changes what the viewer shows.
SAVES = [SCENE.replace("radius 0.7", "radus 0.7"), SCENE.replace("color 0.25 0.35 0.55", "color 0.9 0.5 0.1"), SCENE]


def version(url):
    return json.loads(urllib.request.urlopen(url + "status", timeout=60).read())["version"]


def main():
    raycast = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "raycast"))
    saves = int(sys.argv[2]) if len(sys.argv) > 2 else 250
    folder = tempfile.mkdtemp(prefix="raycast-save-stress-")
    path = os.path.join(folder, "scene.txt")
    with open(path, "w") as f:
        f.write(SCENE)
    server = subprocess.Popen([raycast, "view", "scene.txt", "--port", "0", "-q"], cwd=folder,
                              stdout=subprocess.PIPE, text=True)
    busy = []
    wrong = 0
    start = time.time()
    try:
        url = server.stdout.readline().strip()
        if not url.startswith("http://"):
            print("raycast view printed no URL: %r" % url)
            return 2
        while version(url) < 1:
            time.sleep(0.01)
        # The load: busy loops at normal priority, and this writer below them.
        busy = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(2 * (os.cpu_count() or 1))]
        os.nice(19)
        expected = version(url)
        for save in range(saves):
            with open(path, "w") as f:
                f.write(SAVES[save % len(SAVES)])
            expected += 1
            deadline = time.time() + 30
            while version(url) < expected and time.time() < deadline:
                time.sleep(0.005)
            time.sleep(0.25)  # a second version, if this save makes one, comes within this
            shown = version(url)
            if shown != expected:
                wrong += 1
                print("save %d: version %d, expected %d (%s)" % (save + 1, shown, expected,
                      "one save, two versions" if shown > expected else "the save was not loaded"), flush=True)
                expected = shown
    finally:
        for process in busy:
            process.kill()
        server.terminate()
        server.wait()
        shutil.rmtree(folder, ignore_errors=True)
    print("%d saves, %d not counted as one version each, in %.0f s" % (saves, wrong, time.time() - start))
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main())
