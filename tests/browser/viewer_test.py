#!/usr/bin/env python3
"""raycast view in a real headless Chromium, driven by Selenium (docs/viewer.md).

On a scene this test writes (a mirror ball, a red ball, a floor): the page shows the server's
image; a click on the mirror ball lists a reflected ray in the ray tree and draws the rays over
the image; editing the file updates the image; a typo shows the located error and keeps the last
image; a typed number and a ctrl-drag move a light, the page shows /image with the light there
and draws the light where the camera sees it, and a save keeps the moved light; a drag moves the
camera and the camera block follows. Screenshots go to the folder given.

    python3 tests/browser/viewer_test.py path/to/raycast [SCREENSHOT_FOLDER]

Exit status: 0 passed, 1 failed, 77 skipped (no Selenium, Chromium or ChromeDriver: install
python3-selenium, chromium and chromium-driver).
"""
import base64
import os
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

SKIP = 77

try:
    from selenium import webdriver
    from selenium.webdriver.chrome.options import Options
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
except ImportError:
    print("skipped: python3-selenium is not installed")
    sys.exit(SKIP)

# 320x240, angle 40 spanning both axes (the course's reading): f_x = 160/tan 20° = 439.6. The
# mirror ball's centre (-1.2, 0, 0), 8 in front of the camera, is at x = 160 - 439.6 * 1.2/8 = 94.1,
# on the middle row y = 120 from the bottom, that is row 119 from the top.
SCENE = """PerspectiveCamera {
    center 0 0 8
    direction 0 0 -1
    up 0 1 0
    angle 40
    width 320
    height 240
}
Lights {
    numLights 2
    PointLight { position 3 5 6 color 0.8 0.8 0.8 }
    DirectionalLight { direction -0.3 -1 -0.6 color 0.4 0.4 0.4 }
}
Background { color 0.25 0.35 0.55 }
Materials {
    numMaterials 3
    Material { diffuseColor 0.05 0.05 0.05 specularColor 0.7 0.7 0.7 shininess 60 reflectiveColor 0.85 0.85 0.85 }
    Material { diffuseColor 0.8 0.2 0.15 specularColor 0.3 0.3 0.3 shininess 20 }
    Material { diffuseColor 0.6 0.6 0.55 }
}
Group {
    numObjects 3
    MaterialIndex 0
    Sphere { center -1.2 0 0 radius 1 }
    MaterialIndex 1
    Sphere { center 1.3 -0.3 0.5 radius 0.7 }
    MaterialIndex 2
    Plane { normal 0 1 0 offset -1 }
}
"""
MIRROR_PIXEL = (94, 119)
BACKGROUND_PIXEL = (300, 10)


class Failure(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


# 90 s: a wait ends as soon as its condition holds, and on a machine busy with other work (a
# parallel build and test run on two cores) the 16-sample image once took longer than 30 s.
def wait_until(what, condition, timeout=90.0):
    start = time.time()
    while True:
        value = condition()
        if value:
            return value
        if time.time() - start > timeout:
            raise Failure("timed out waiting until " + what)
        time.sleep(0.05)


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    raycast = os.path.abspath(sys.argv[1])
    shots = os.path.abspath(sys.argv[2]) if len(sys.argv) > 2 else None
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    chromedriver = shutil.which("chromedriver")
    if not chromium or not chromedriver:
        print("skipped: chromium and chromium-driver are not installed")
        return SKIP
    if shots:
        os.makedirs(shots, exist_ok=True)

    folder = tempfile.mkdtemp(prefix="raycast-browser-")
    scene_path = os.path.join(folder, "scene.txt")
    with open(scene_path, "w") as f:
        f.write(SCENE)
    server = subprocess.Popen([raycast, "view", "scene.txt", "--port", "0", "--bounces", "3", "--shadows", "-q"],
                              cwd=folder, stdout=subprocess.PIPE, text=True)
    driver = None
    try:
        url = server.stdout.readline().strip()
        check(url.startswith("http://127.0.0.1:"), "raycast view printed no URL: %r" % url)
        options = Options()
        for argument in ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                         "--disable-background-networking", "--disable-component-update", "--disable-sync",
                         "--disable-dev-shm-usage", "--window-size=1400,900",
                         "--user-data-dir=" + os.path.join(folder, "chromium")]:
            options.add_argument(argument)
        options.binary_location = chromium
        driver = webdriver.Chrome(service=Service(chromedriver), options=options)
        driver.set_script_timeout(30)
        run(driver, url, scene_path, shots)
        print("passed")
        return 0
    except Failure as failure:
        print("FAILED:", failure)
        if driver is not None and shots:
            driver.save_screenshot(os.path.join(shots, "failure.png"))
        return 1
    finally:
        if driver is not None:
            driver.quit()
        server.terminate()
        server.wait(timeout=10)
        shutil.rmtree(folder, ignore_errors=True)


def image_state(driver):
    return driver.execute_script(
        "const i = document.getElementById('image');"
        "return {width: i.naturalWidth, height: i.naturalHeight, spp: i.dataset.spp || '', version: i.dataset.version || '',"
        "        query: i.dataset.query || '', src: i.src};")


def displayed_image_bytes(driver):
    """The bytes of the image the page shows (its blob), fetched inside the page."""
    encoded = driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "fetch(document.getElementById('image').src).then(r => r.arrayBuffer()).then(b => {"
        "  let s = ''; const u = new Uint8Array(b); for (let i = 0; i < u.length; ++i) s += String.fromCharCode(u[i]);"
        "  done(btoa(s)); }).catch(e => done(null));")
    check(encoded is not None, "the page's image could not be read back")
    return base64.b64decode(encoded)


def pixel(driver, x, y):
    """The colour the page shows at image pixel (x, y), y from the top."""
    return driver.execute_script(
        "const i = document.getElementById('image'); const c = document.createElement('canvas');"
        "c.width = i.naturalWidth; c.height = i.naturalHeight; const g = c.getContext('2d'); g.drawImage(i, 0, 0);"
        "return Array.from(g.getImageData(arguments[0], arguments[1], 1, 1).data.slice(0, 3));", x, y)


def wait_for_image(driver, version, spp):
    return wait_until("the page shows version %s at %s samples" % (version, spp),
                      lambda: (lambda s: s if s["version"] == str(version) and s["spp"] == str(spp) else None)(
                          image_state(driver)))


def settled_image(driver, url):
    """Waits until the page shows its last image for the current view (16 samples, the query the
    page would ask now: it asks nothing more), then returns what /image serves for that query.
    Asked earlier, /image would cancel the page's own render (409), or be cancelled by it."""
    query = wait_until("the page settles on the current view",
                       lambda: (lambda s, q: q if s["spp"] == "16" and s["query"] == q else None)(
                           image_state(driver), driver.execute_script("return renderParams({spp: 16});")))
    return urllib.request.urlopen(url + "image?" + query, timeout=60).read()


def click_image(driver, x, y):
    """Clicks image pixel (x, y), or its neighbour: offsets are whole CSS pixels from the overlay's
    centre (160, 120). Returns the pixel the page picked."""
    overlay = driver.find_element(By.ID, "overlay")
    ActionChains(driver).move_to_element_with_offset(overlay, x - 160, y - 120).click().perform()
    picked = wait_until("the page picks a pixel", lambda: driver.execute_script("return picked;"))
    check(abs(picked["x"] - x) <= 1 and abs(picked["y"] - y) <= 1, "clicked %s, picked %s" % ((x, y), picked))
    return picked["x"], picked["y"]


def run(driver, url, scene_path, shots):
    driver.get(url)
    # The page shows the server's image: after refining to 16 samples, the very bytes of /image.
    state = wait_for_image(driver, 1, 16)
    check(state["width"] == 320 and state["height"] == 240, "the image is %dx%d" % (state["width"], state["height"]))
    params = driver.execute_script("return renderParams({spp: 16});")
    served = urllib.request.urlopen(url + "image?" + params, timeout=60).read()
    check(displayed_image_bytes(driver) == served, "the page does not show the image /image serves")
    first_bytes = served

    # A click on the mirror ball: its ray tree lists a reflected ray, and rays are drawn.
    picked = click_image(driver, *MIRROR_PIXEL)
    wait_until("the ray tree lists a reflected ray",
               lambda: driver.find_elements(By.CSS_SELECTOR, "#tree li[data-kind='reflected']"))
    check(driver.find_elements(By.CSS_SELECTOR, "#tree li[data-kind='shadow']"), "no shadow rays in the tree")
    check("(%d, %d)" % picked in driver.find_element(By.ID, "pixel").text, "the tree is of another pixel")
    drawn = driver.execute_script(
        "const o = document.getElementById('overlay'); const d = o.getContext('2d').getImageData(0, 0, o.width, o.height).data;"
        "let n = 0; for (let i = 3; i < d.length; i += 4) n += d[i] > 0; return n;")
    check(drawn > 50, "the rays are not drawn over the image (%d pixels)" % drawn)
    if shots:
        driver.save_screenshot(os.path.join(shots, "viewer_ray_tree.png"))

    # Editing the file: a new version, a new background in the image.
    before = pixel(driver, *BACKGROUND_PIXEL)
    with open(scene_path) as f:
        scene = f.read()
    with open(scene_path, "w") as f:
        f.write(scene.replace("color 0.25 0.35 0.55", "color 0.9 0.5 0.1"))
    wait_for_image(driver, 2, 16)
    after = pixel(driver, *BACKGROUND_PIXEL)
    check(after != before, "the background did not change: %s" % after)
    check(abs(after[0] - 229) <= 1 and abs(after[1] - 127) <= 1 and abs(after[2] - 25) <= 1,
          "the new background is %s, not 0.9 0.5 0.1" % after)
    good_bytes = displayed_image_bytes(driver)

    # A typo: the located error over the last good image, which stays.
    with open(scene_path, "w") as f:
        f.write(scene.replace("color 0.25 0.35 0.55", "color 0.9 0.5 0.1").replace("radius 0.7", "radus 0.7"))
    wait_until("the error is shown", lambda: driver.find_element(By.ID, "errors").is_displayed())
    text = driver.find_element(By.ID, "errors").text
    check("scene.txt:26:34: error: unknown field 'radus' in Sphere; did you mean 'radius'?" in text,
          "the error is not located as expected: %r" % text)
    check("^" in text, "the error has no caret: %r" % text)
    wait_for_image(driver, 3, 16)
    check(displayed_image_bytes(driver) == good_bytes, "the last good image did not stay")
    if shots:
        driver.save_screenshot(os.path.join(shots, "viewer_error.png"))

    # Fixed: the error goes.
    with open(scene_path, "w") as f:
        f.write(scene)
    wait_until("the error is gone", lambda: not driver.find_element(By.ID, "errors").is_displayed())
    wait_for_image(driver, 4, 16)
    check(displayed_image_bytes(driver) == first_bytes, "back to the first file, but not to the first image")

    # The lights: their block is the file's; a number typed for light 0 moves it, and the page
    # shows /image with light0= there; a ctrl-drag moves it across the view (not the camera); the
    # reset brings the file's lights and the first image back.
    lights_text = lambda: driver.find_element(By.ID, "lights-text").get_attribute("value")
    check("numLights 2\n    PointLight {\n        position 3 5 6\n        color 0.8 0.8 0.8\n    }\n" in lights_text(),
          "the lights block is not the file's: %r" % lights_text())
    tree_before = driver.find_element(By.ID, "tree").text
    check(("pixel (%d, %d)" % picked) in tree_before, "the picked pixel's tree is gone: %r" % tree_before)
    driver.execute_script("const f = document.getElementById('light0-x'); f.value = '-3';"
                          "f.dispatchEvent(new Event('change'));")
    wait_until("the lights block follows the number", lambda: "position -3 5 6" in lights_text())
    params = driver.execute_script("return renderParams({spp: 16});")
    check("light0=-3%2C5%2C6" in params and "light1" not in params, "the query does not move light 0 alone: " + params)
    served = settled_image(driver, url)
    check(served != first_bytes, "moving the light changed nothing")
    check(displayed_image_bytes(driver) == served, "the page does not show /image with the light moved")
    # The picked pixel is the same surface, lit anew: its tree is asked for again, and changes.
    wait_until("the picked pixel's tree follows the light",
               lambda: (lambda t: ("pixel (%d, %d)" % picked) in t and t != tree_before)(
                   driver.find_element(By.ID, "tree").text))
    camera_block = driver.find_element(By.ID, "camera-text").get_attribute("value")
    overlay = driver.find_element(By.ID, "overlay")
    ActionChains(driver).key_down(Keys.CONTROL).move_to_element_with_offset(overlay, 0, 0).click_and_hold() \
        .move_by_offset(40, 0).move_by_offset(20, -20).release().key_up(Keys.CONTROL).perform()
    wait_until("a ctrl-drag moves the light", lambda: "position -3 5 6" not in lights_text())
    check(driver.find_element(By.ID, "camera-text").get_attribute("value") == camera_block,
          "the ctrl-drag moved the camera too")
    dragged_x = float(driver.find_element(By.ID, "light0-x").get_attribute("value"))
    check(dragged_x > -3, "dragged right, the light went to x = %s" % dragged_x)
    dragged = settled_image(driver, url)
    check(dragged != served, "dragging the light changed nothing")
    check(displayed_image_bytes(driver) == dragged, "the page does not show /image with the light dragged")
    if shots:
        driver.save_screenshot(os.path.join(shots, "viewer_lights.png"))
    # A save that moves the other light and recolours this one: the moved light stays where the
    # drag put it, and the rest is the file's (the other light was sent as it had been).
    dragged_block = lights_text()
    with open(scene_path, "w") as f:
        f.write(scene.replace("PointLight { position 3 5 6 color 0.8 0.8 0.8 }",
                              "PointLight { position 3 5 6 color 0.8 0.6 0.4 }")
                .replace("direction -0.3 -1 -0.6", "direction 0.3 -1 -0.6"))
    wait_for_image(driver, 5, 16)
    params = driver.execute_script("return renderParams({spp: 16});")
    check("light0=" in params and "light1" not in params, "after the save, the query is " + params)
    block = lights_text()
    check("position " + dragged_block.split("position ")[1].split("\n")[0] in block, "the dragged light moved: %r" % block)
    check("color 0.8 0.6 0.4" in block and "direction 0.3 -1 -0.6" in block,
          "the save's colour and direction are not taken: %r" % block)
    with open(scene_path, "w") as f:
        f.write(scene)
    wait_for_image(driver, 6, 16)
    driver.find_element(By.ID, "reset-lights").click()
    wait_until("the reset brings the first image back", lambda: displayed_image_bytes(driver) == first_bytes)
    check("position 3 5 6" in lights_text(), "the reset did not bring the file's lights back")

    # A point light in view is drawn where the camera sees it: at (1, 0.5, 2), 6 in front of the
    # camera, x = 160 + 439.6 * 1/6 = 233.3 and, with f_y = 120/tan 20° = 329.7 (the angle spans
    # both axes), y = 120 + 329.7 * 0.5/6 = 147.5 from the bottom; pixel x's ray is at x (the
    # course's pixel offset 0), so the light is in pixel column 233 and row 240 - 148 = 92.
    for axis, value in zip("xyz", ["1", "0.5", "2"]):
        driver.execute_script("const f = document.getElementById('light0-' + arguments[0]); f.value = arguments[1];"
                              "f.dispatchEvent(new Event('change'));", axis, value)
    marker = lambda: driver.execute_script(
        "return Array.from(document.getElementById('overlay').getContext('2d').getImageData(233, 92, 1, 1).data);")
    wait_until("the light is drawn where the camera sees it", lambda: marker() == [255, 230, 128, 255])
    # With the angle spanning the height alone, f_x = f_y = 329.7: column 160 + 329.7/6 = 214.9.
    driver.execute_script("const f = document.getElementById('fov'); f.value = 'vertical';"
                          "f.dispatchEvent(new Event('change'));")
    marker = lambda: driver.execute_script(
        "return Array.from(document.getElementById('overlay').getContext('2d').getImageData(214, 92, 1, 1).data);")
    wait_until("the light is drawn where the camera with a vertical angle sees it",
               lambda: marker() == [255, 230, 128, 255])
    driver.execute_script("const f = document.getElementById('fov'); f.value = 'both';"
                          "f.dispatchEvent(new Event('change'));")
    if shots:
        driver.execute_script("window.scrollTo(0, 0);")
        driver.save_screenshot(os.path.join(shots, "viewer_light_marker.png"))
    driver.find_element(By.ID, "reset-lights").click()
    wait_until("the reset brings the first image back again", lambda: displayed_image_bytes(driver) == first_bytes)

    # A drag orbits the camera: a new image, and the camera block follows.
    block_before = driver.find_element(By.ID, "camera-text").get_attribute("value")
    overlay = driver.find_element(By.ID, "overlay")
    ActionChains(driver).move_to_element_with_offset(overlay, 0, 0).click_and_hold().move_by_offset(30, 0) \
        .move_by_offset(40, 10).release().perform()
    block_after = wait_until("the camera block changes",
                             lambda: (lambda b: b if b != block_before else None)(
                                 driver.find_element(By.ID, "camera-text").get_attribute("value")))
    check(block_after.startswith("PerspectiveCamera {") and "width 320" in block_after,
          "the camera block is not in the scene's grammar: %r" % block_after)
    moved = wait_until("a new image after the drag",
                       lambda: (lambda s: s if s["spp"] == "16" and displayed_image_bytes(driver) != first_bytes
                                else None)(image_state(driver)))
    check(moved["width"] == 320, "the dragged view has another size")
    if shots:
        driver.save_screenshot(os.path.join(shots, "viewer_orbit.png"))


if __name__ == "__main__":
    sys.exit(main())
