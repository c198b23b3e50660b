#!/usr/bin/env python3
"""demo.page: opens the demo's results page in headless Chromium and fails if a figure is
missing or blank.

Usage: check_results_page.py RESULTS_DIR [--self-test] [--expect-pictures]

For RESULTS_DIR/index.html (written by lieservo_demo) it
  1. loads a copy of the page with a probe script appended in Chromium (--dump-dom), which
     reports for every <img> whether the browser decoded it (naturalWidth > 0) and where it
     was laid out;
  2. takes a full-page screenshot of the same copy at the same width;
  3. checks each figure's box in the screenshot: at least MIN_SIZE pixels each way and at
     least MIN_INK of its pixels drawn (darker than the white background).
  4. for each time-lapse of a pushing case (<img class="picture">, RESULTS_DIR/<plot>/<object>.png),
     reads the PNG itself and requires the object's colour in it: at least MIN_OBJECT of the
     pixels below the caption bar fall in the object's colour class (OBJECT_COLOURS, HSV);
     the supports, the sensors, the target and the paths fall in none of them.
  5. that the page opens with the pushing figure beside the paper's and that no row of the
     summary table marked "(reported)" says "yes" (check_summary);
  6. with --expect-pictures (a build with the renderer), that every pushing plot (but the
     opposition angles), the tracking errors and both following plots have their pictures on
     the page.
With --self-test it first checks itself: in a scratch copy of the results it blanks one
figure (a white SVG of the same size), points another <img> at a file that is not there and,
when the page has time-lapses, paints one of them grey, and requires all to be reported.

Exit status: 0 pass, 1 fail, 77 (CTest's skip) when Chromium or OpenCV is not installed.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

MIN_SIZE = 100     # px: a figure drawn smaller than this is not readable
MIN_INK = 0.005    # fraction of the figure's pixels darker than the background
BACKGROUND = 240   # a pixel whose darkest channel is below this counts as ink
WIDTH = 1280       # browser window width (px)
MIN_OBJECT = 0.002  # fraction of a time-lapse's pixels in the object's colour class
CAPTION = 26        # px: the caption bar at the top of each rendered frame (white)

# OpenCV HSV (H 0-180, S and V 0-255): (H ranges, minimum S, minimum V) per colour class,
# and the class of each object by a word of its name (examples/sim/src/task_common.cpp).
COLOUR_CLASSES = {
    "blue": ([(100, 130)], 100, 50),
    "red": ([(0, 6), (174, 180)], 150, 60),
    "yellow": ([(18, 35)], 120, 100),
    "green": ([(45, 85)], 80, 40),
    "cyan": ([(86, 99)], 50, 150),
}
OBJECT_COLOURS = {"blue": "blue", "windex": "blue", "red": "red", "coffee": "red", "yellow": "yellow",
                  "mustard": "yellow", "glass": "green", "cleaner": "cyan"}

PROBE = """<script>
window.addEventListener('load', function () {
  var figures = [];
  document.querySelectorAll('img').forEach(function (im) {
    // the image's content box: its border and padding are the page's, not the figure's
    var r = im.getBoundingClientRect(), s = getComputedStyle(im);
    var px = function (v) { return parseFloat(v) || 0; };
    var l = px(s.borderLeftWidth) + px(s.paddingLeft), t = px(s.borderTopWidth) + px(s.paddingTop);
    var w = r.width - l - px(s.borderRightWidth) - px(s.paddingRight);
    var h = r.height - t - px(s.borderBottomWidth) - px(s.paddingBottom);
    figures.push({src: im.getAttribute('src'), loaded: im.complete && im.naturalWidth > 0,
                  x: r.left + l + window.scrollX, y: r.top + t + window.scrollY, w: w, h: h});
  });
  var pre = document.createElement('pre');
  pre.id = 'figure-probe';
  pre.textContent = JSON.stringify({height: document.documentElement.scrollHeight,
                                    figures: figures});
  document.body.appendChild(pre);
});
</script>
"""


def find_chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def chromium(browser, args):
    cmd = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
           "--allow-file-access-from-files", "--virtual-time-budget=10000"] + args
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                          timeout=120)


def check_page(browser, cv2, results, quiet=False):
    """Returns the list of problems found on results/index.html (empty = pass); prints what
    each figure shows unless quiet."""
    page = os.path.join(results, "index.html")
    if not os.path.isfile(page):
        return [f"{page} does not exist"]
    html = open(page, encoding="utf-8").read()
    if "</body>" not in html:
        return [f"{page} has no </body>"]
    probe_page = os.path.join(results, ".page_probe.html")
    shot = os.path.join(results, ".page_screenshot.png")
    with open(probe_page, "w", encoding="utf-8") as f:
        f.write(html.replace("</body>", PROBE + "</body>"))
    url = "file://" + os.path.abspath(probe_page)
    try:
        dom = chromium(browser, [f"--window-size={WIDTH},1000", "--dump-dom", url]).stdout
        m = re.search(r'<pre id="figure-probe">(.*?)</pre>', dom, re.S)
        if not m:
            return ["Chromium did not run the probe script (no layout report)"]
        layout = json.loads(m.group(1).replace("&quot;", '"').replace("&amp;", "&"))
        height = int(layout["height"]) + 100
        chromium(browser, [f"--window-size={WIDTH},{height}", f"--screenshot={shot}", url])
        image = cv2.imread(shot)
    finally:
        os.remove(probe_page)
    if image is None:
        return ["Chromium wrote no screenshot"]
    os.remove(shot)
    problems = []
    if not layout["figures"]:
        problems.append("the page shows no figures")
    for fig in layout["figures"]:
        src = fig["src"]
        if not fig["loaded"]:
            problems.append(f"{src}: missing (the browser could not load it)")
            continue
        # whole pixels inside the content box (its edge pixels are blended with the border)
        x, y = int(fig["x"]) + 1, int(fig["y"]) + 1
        w, h = int(fig["w"]) - 2, int(fig["h"]) - 2
        if w < MIN_SIZE or h < MIN_SIZE:
            problems.append(f"{src}: drawn {w}x{h} px, under {MIN_SIZE} px")
            continue
        box = image[y:y + h, x:x + w]
        if box.shape[0] < h or box.shape[1] < w:
            problems.append(f"{src}: outside the screenshot ({x},{y} {w}x{h})")
            continue
        ink = float((box.min(axis=2) < BACKGROUND).mean())
        if ink < MIN_INK:
            problems.append(f"{src}: blank ({100 * ink:.2f} % of its pixels drawn, "
                            f"under {100 * MIN_INK:.1f} %)")
        elif not quiet:
            print(f"  {src}: {w}x{h} px, {100 * ink:.1f} % drawn")
    problems += check_time_lapses(cv2, results, html, quiet)
    return problems


def object_colour(name):
    for word, colour in OBJECT_COLOURS.items():
        if word in name:
            return colour
    return None


def check_time_lapses(cv2, results, html, quiet=False):
    """Each pushing case's time-lapse shows its object: enough pixels of its colour class."""
    problems = []
    for src in re.findall(r'<img class="picture" src="([^"]+)"', html):
        name = os.path.splitext(os.path.basename(src))[0]
        colour = object_colour(name)
        if colour is None:  # a strip of frames (tracking, following): no object to find
            continue
        image = cv2.imread(os.path.join(results, src))
        if image is None:
            problems.append(f"{src}: not a readable image")
            continue
        hsv = cv2.cvtColor(image[CAPTION:], cv2.COLOR_BGR2HSV)
        ranges, s_min, v_min = COLOUR_CLASSES[colour]
        h, sat, val = hsv[..., 0], hsv[..., 1], hsv[..., 2]
        hue = sum(((h >= lo) & (h <= hi)) for lo, hi in ranges).astype(bool)
        share = float((hue & (sat >= s_min) & (val >= v_min)).mean())
        if share < MIN_OBJECT:
            problems.append(f"{src}: the object is not in it ({100 * share:.2f} % {colour}, "
                            f"under {100 * MIN_OBJECT:.1f} %)")
        elif not quiet:
            print(f"  {src}: {100 * share:.1f} % {colour}")
    return problems


def check_expected_pictures(results):
    """Every task's plot has its pictures (time-lapses or strips of frames) on the page."""
    html = open(os.path.join(results, "index.html"), encoding="utf-8").read()
    pictures = re.findall(r'<img class="picture" src="([^"]+)"', html)
    folders = {p.split("/")[0] for p in pictures}
    plots = [m for m in re.findall(r'<img src="([^"/]+)\.svg"', html)
             if m.startswith("pushing_") and m != "pushing_dual_opposition"]
    wanted = plots + ["tracking_errors", "following_ramp", "following_dome"]
    problems = [f"{w}.svg: no pictures beside it on the page" for w in wanted if w not in folders]
    if not problems:
        print(f"  pictures beside all {len(wanted)} task plots ({len(pictures)} in all)")
    return problems


def check_summary(html):
    """The page opens with the pushing figure (simulation beside the paper), and no row of the
    summary table that only reports ("(reported)" in it, or "reported" in its pass column) says
    it passed."""
    problems = []
    if not re.search(r'<img id="summary" src="[^"]+\.svg"', html):
        problems.append("summary: the page has no pushing figure beside the paper's (img#summary)")
    for row in re.findall(r"<tr>(.*?)</tr>", html):
        cells = re.findall(r"<td[^>]*>(.*?)</td>", row)
        if cells and "(reported)" in row and cells[-1] != "reported":
            problems.append(f"summary: a reported row says '{cells[-1]}': {cells[1] if len(cells) > 1 else row}")
    return problems


def self_test(browser, cv2, results):
    """The check must catch a blank figure, a missing one and a time-lapse without its object.
    It runs on a page of those three alone (the real page's head and markup), so that Chromium
    draws three images instead of the whole page twice."""
    with tempfile.TemporaryDirectory() as scratch:
        copy = os.path.join(scratch, "results")
        shutil.copytree(results, copy)
        html = open(os.path.join(copy, "index.html"), encoding="utf-8").read()
        svgs = re.findall(r'<img src="([^"]+\.svg)"', html)
        if len(svgs) < 2:
            return ["self-test: the page has fewer than two SVG figures"]
        if "<body>" not in html:
            return ["self-test: the page has no <body>"]
        blank = svgs[0]
        with open(os.path.join(copy, blank), "w", encoding="utf-8") as f:
            f.write('<svg xmlns="http://www.w3.org/2000/svg" width="1200" height="400">'
                    '<rect width="100%" height="100%" fill="white"/></svg>')
        body = f'<img src="{blank}">\n<img src="no_such_figure.svg">\n'
        wanted = {f"{blank}: blank": False, "no_such_figure.svg: missing": False}
        lapses = [x for x in re.findall(r'<img class="picture" src="([^"]+)"', html)
                  if object_colour(os.path.basename(x))]
        if lapses:  # a time-lapse without its object's colour (all grey)
            path = os.path.join(copy, lapses[0])
            grey = cv2.cvtColor(cv2.cvtColor(cv2.imread(path), cv2.COLOR_BGR2GRAY), cv2.COLOR_GRAY2BGR)
            cv2.imwrite(path, grey)
            body += f'<img class="picture" src="{lapses[0]}">\n'
            wanted[f"{lapses[0]}: the object is not in it"] = False
        head = html[:html.index("<body>") + len("<body>")]
        open(os.path.join(copy, "index.html"), "w", encoding="utf-8").write(
            head + "\n" + body + "</body></html>\n")
        found = check_page(browser, cv2, copy, quiet=True)
        for p in found:
            for w in wanted:
                if p.startswith(w):
                    wanted[w] = True
        return [f"self-test: the check did not report '{w}'" for w, ok in wanted.items() if not ok]


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    results = sys.argv[1]
    browser = find_chromium()
    if browser is None:
        print("demo.page skipped: Chromium is not installed (bash .ci/install-deps test)")
        return 77
    try:
        import cv2
    except ImportError:
        print("demo.page skipped: OpenCV for Python is not installed (python3-opencv)")
        return 77
    problems = []
    if "--self-test" in sys.argv[2:]:
        fake = ('<tr><td>dual-arm push</td><td>blue circle, foam (mm) (reported)</td><td>1</td><td>2</td>'
                '<td>yes</td></tr>')
        if len(check_summary(fake)) != 2:
            problems.append("self-test: check_summary missed a reported row saying yes or a missing figure")
        problems += self_test(browser, cv2, results)
        if not problems:
            print("self-test: a blank figure, a missing one and a time-lapse without its object "
                  "(when the page has time-lapses) are all reported")
    problems += check_page(browser, cv2, results)
    problems += check_summary(open(os.path.join(results, "index.html"), encoding="utf-8").read())
    if "--expect-pictures" in sys.argv[2:]:
        problems += check_expected_pictures(results)
    for p in problems:
        print("demo.page FAIL:", p)
    if not problems:
        print(f"demo.page: every figure on {results}/index.html is there and drawn")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
