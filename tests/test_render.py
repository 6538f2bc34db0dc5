#!/usr/bin/python3
"""sluice render, end to end: runs a tiny case, renders it, and decodes the GIF and PNG files with an
independent reader (PIL, Debian's python3-pil). Checks frame count, size, timing and looping, that
GIF frames are the same pictures as the PNG snapshots, that the picture has an equal aspect ratio
and particles of their physical size, that each particle lands where it is and in the colour the
map gives its value (against matplotlib's viridis, typed in below), and the clear errors.

    /usr/bin/python3 tests/test_render.py --sluice build/release/sluice
"""
import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np
from PIL import Image

SLUICE = None

# A 2 m x 1 m open tank with a 0.5 m x 0.5 m block of water in its lower left corner (dx = 5 cm).
CASE = """
[case]
name = "tiny"
description = "render test"
[domain]
dx = 0.05
[tank]
width = 2.0
height = 1.0
lid = false
[time]
end = 0.1
[output]
interval = 0.025
[[water]]
min = [0.0, 0.0]
max = [0.5, 0.5]
"""
FRAMES = 5  # t = 0, 0.025, ..., 0.1
DX = 0.05

# A 3D dam break: a 0.25 m x 0.2 m x 0.5 m column in one corner of an open 0.6 m x 0.4 m x 0.8 m tank.
CASE_3D = """
[case]
name = "tiny3d"
description = "render test in 3D"
[domain]
dimension = 3
dx = 0.05
[tank]
width = 0.6
depth = 0.4
height = 0.8
lid = false
[physics]
gravity = [0.0, 0.0, -9.81]
[time]
end = 0.1
[output]
interval = 0.05
[[water]]
min = [0.0, 0.0, 0.0]
max = [0.25, 0.2, 0.5]
"""
FRAMES_3D = 3  # t = 0, 0.05, 0.1
VIEWS = ["iso", "front", "side", "top"]

# matplotlib's viridis (_cm_listed.py, _viridis_data) at entries 0, 8, 16, ..., 248 and 255, times 255.
VIRIDIS_AT = list(range(0, 256, 8)) + [255]
VIRIDIS = [
    (68, 1, 84), (71, 13, 96), (72, 24, 106), (72, 35, 116), (71, 45, 123), (69, 55, 129), (66, 64, 134),
    (62, 73, 137), (59, 82, 139), (55, 91, 141), (51, 99, 141), (47, 107, 142), (44, 114, 142), (41, 122, 142),
    (38, 130, 142), (35, 137, 142), (33, 145, 140), (31, 152, 139), (31, 160, 136), (34, 167, 133),
    (40, 174, 128), (50, 182, 122), (63, 188, 115), (78, 195, 107), (94, 201, 98), (112, 207, 87),
    (132, 212, 75), (152, 216, 62), (173, 220, 48), (194, 223, 35), (216, 226, 25), (236, 229, 27),
    (253, 231, 37)]


def viridis(t):
    t = min(max(t, 0.0), 1.0) * 255.0
    xs = np.array(VIRIDIS_AT, dtype=float)
    table = np.array(VIRIDIS, dtype=float)
    return np.array([np.interp(t, xs, table[:, c]) for c in range(3)])


def sluice(*args, check=True):
    r = subprocess.run([SLUICE, *map(str, args)], capture_output=True, text=True, timeout=300)
    if check and r.returncode != 0:
        raise AssertionError(f"sluice {' '.join(map(str, args))} failed ({r.returncode}):\n{r.stdout}{r.stderr}")
    return r


def rgb(path):
    return np.asarray(Image.open(path).convert("RGB")).astype(int)


def is_grey(img):
    return (img[:, :, 0] == img[:, :, 1]) & (img[:, :, 1] == img[:, :, 2])


class Geometry:
    """Where the world is in a picture, measured from the picture alone: the bounding boxes of the wall
    pixels and of the water pixels at t = 0, against the particle positions in the frame."""

    def __init__(self, img, frame):
        grey = is_grey(img)
        white = grey & (img[:, :, 0] == 255)
        values, counts = np.unique(img[grey & ~white][:, 0], return_counts=True)
        self.wall_rgb = int(values[np.argmax(counts)])  # the walls: the commonest grey that is not white
        wall = grey & (img[:, :, 0] == self.wall_rgb)
        cols = np.nonzero(wall.sum(axis=0) >= 10)[0]  # text never stacks 10 pixels of one grey
        rows = np.nonzero(wall.sum(axis=1) >= 10)[0]
        self.wall_box = (cols.min(), rows.min(), cols.max() + 1, rows.max() + 1)  # x0, y0, x1, y1 (pixels)
        water = ~grey
        water[:, self.wall_box[2]:] = False  # the colour bar is right of the tank
        ys, xs = np.nonzero(water)
        self.water_box = (xs.min(), ys.min(), xs.max() + 1, ys.max() + 1)

        x, kind = frame["x"], frame["kind"]
        w, f = x[kind == 1], x[kind == 0]
        wall_span = w.max(axis=0) - w.min(axis=0)
        water_span = f.max(axis=0) - f.min(axis=0)
        # Each box is the centres' span times the scale plus one disc diameter: the difference of the
        # two boxes gives the scale, in x and in y separately.
        self.sx = ((self.wall_box[2] - self.wall_box[0]) - (self.water_box[2] - self.water_box[0])) / (
            wall_span[0] - water_span[0])
        self.sy = ((self.wall_box[3] - self.wall_box[1]) - (self.water_box[3] - self.water_box[1])) / (
            wall_span[1] - water_span[1])
        self.diameter_px = (self.water_box[2] - self.water_box[0]) - water_span[0] * self.sx
        # The water block's centre in the world and in the picture (y up in the world, down in pictures).
        self.cw = (f.min(axis=0) + f.max(axis=0)) / 2
        self.cp = ((self.water_box[0] + self.water_box[2]) / 2, (self.water_box[1] + self.water_box[3]) / 2)

    def pixel(self, x, y):
        return (int(math.floor(self.cp[0] + (x - self.cw[0]) * self.sx)),
                int(math.floor(self.cp[1] - (y - self.cw[1]) * self.sy)))


class RenderTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="sluice_render_")
        case = os.path.join(cls.tmp, "tiny.toml")
        with open(case, "w") as f:
            f.write(CASE)
        cls.run_dir = os.path.join(cls.tmp, "run")
        # `sluice run --render` draws the animation at the end of the run.
        cls.run_output = sluice("run", case, "-o", cls.run_dir, "-q", "--render", "speed")
        cls.frame0 = dict(np.load(os.path.join(cls.run_dir, "frames", "frame_000000.npz")))
        case3d = os.path.join(cls.tmp, "tiny3d.toml")
        with open(case3d, "w") as f:
            f.write(CASE_3D)
        cls.run3d = os.path.join(cls.tmp, "run3d")
        sluice("run", case3d, "-o", cls.run3d, "-q")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def out(self, name):
        return os.path.join(self.tmp, name)

    def test_run_render_writes_the_animation(self):
        gif = os.path.join(self.run_dir, "speed.gif")
        self.assertTrue(os.path.exists(gif), self.run_output.stdout + self.run_output.stderr)
        with Image.open(gif) as im:
            self.assertEqual(im.format, "GIF")
            self.assertEqual(im.n_frames, FRAMES)

    def test_gif_frames_size_timing_and_looping(self):
        gif = self.out("a.gif")
        r = sluice("render", self.run_dir, "--fps", 10, "--size", "640x360", "-o", gif)
        self.assertIn("5 frames", r.stdout)
        with Image.open(gif) as im:
            self.assertEqual(im.format, "GIF")
            self.assertEqual(im.size, (640, 360))
            self.assertEqual(im.n_frames, FRAMES)
            self.assertEqual(im.info.get("loop"), 0)  # loops forever
            durations = []
            for k in range(im.n_frames):
                im.seek(k)
                durations.append(im.info["duration"])
            self.assertEqual(durations, [100] * FRAMES)  # 10 fps: 100 ms per frame
        # The default: 20 fps, into the run directory, with a default size that is even.
        sluice("render", self.run_dir, "--field", "vy")
        with Image.open(os.path.join(self.run_dir, "vy.gif")) as im:
            self.assertEqual(im.n_frames, FRAMES)
            self.assertEqual(im.info["duration"], 50)
            self.assertEqual(im.size[0] % 2, 0)
            self.assertEqual(im.size[1] % 2, 0)
            self.assertGreater(im.size[0], im.size[1])  # a 2:1 tank: a landscape picture

    def test_gif_frames_are_the_png_snapshots(self):
        gif, snaps = self.out("b.gif"), self.out("snaps")
        sluice("render", self.run_dir, "--field", "pressure", "--size", "640x360", "-o", gif)
        r = sluice("render", self.run_dir, "--field", "pressure", "--size", "640x360", "--format", "png",
                   "-o", snaps)
        names = sorted(os.listdir(snaps))
        self.assertEqual(names, [f"pressure_{k:06}.png" for k in range(FRAMES)], r.stdout)
        with Image.open(gif) as im:
            for k in range(FRAMES):
                im.seek(k)
                frame = np.asarray(im.convert("RGB")).astype(int)
                png = rgb(os.path.join(snaps, names[k]))
                self.assertEqual(png.shape, (360, 640, 3))
                self.assertTrue(np.array_equal(frame, png), f"GIF frame {k} differs from its PNG")
        # The frames differ from one another (the water moves, the time stamp changes).
        self.assertFalse(np.array_equal(rgb(os.path.join(snaps, names[0])), rgb(os.path.join(snaps, names[-1]))))

    def test_snapshots_at_requested_times(self):
        d = self.out("times")
        sluice("render", self.run_dir, "--times", "0,0.05,0.1", "-o", d)
        self.assertEqual(sorted(os.listdir(d)), ["speed_000000.png", "speed_000002.png", "speed_000004.png"])
        one = self.out("one.png")
        sluice("render", self.run_dir, "--times", "0.05", "-o", one)
        with Image.open(one) as im:
            self.assertEqual(im.format, "PNG")
        r = sluice("render", self.run_dir, "--times", "7", check=False)
        self.assertEqual(r.returncode, 2)
        self.assertIn("no frame at t = 7 s", r.stderr)

    def test_particles_land_where_they_are_in_the_maps_colour(self):
        # Pressure at t = 0 is hydrostatic, p = rho0 g (0.5 - y); --range 0:4.905 kPa spans it exactly,
        # so a particle at height y has the colour viridis((0.5 - y) / 0.5).
        png = self.out("p0.png")
        sluice("render", self.run_dir, "--field", "pressure", "--times", "0", "--range", "0:4.905",
               "--size", "800x480", "-o", png)
        img = rgb(png)
        self.assertEqual(img.shape, (480, 800, 3))
        g = Geometry(img, self.frame0)
        # Equal aspect ratio: the same scale in x and y, measured independently.
        self.assertAlmostEqual(g.sx / g.sy, 1.0, delta=0.02)
        # Discs of their physical size: the area dx^2 a particle stands for (diameter 2 dx / sqrt(pi)).
        self.assertAlmostEqual(g.diameter_px, 2 * DX / math.sqrt(math.pi) * g.sx, delta=1.5)
        # Walls in grey.
        self.assertGreater(g.wall_rgb, 80)
        self.assertLess(g.wall_rgb, 200)

        x, kind, p = self.frame0["x"], self.frame0["kind"], self.frame0["p"]
        worst = 0.0
        for i in np.nonzero(kind == 0)[0]:
            px, py = g.pixel(*x[i])
            expected = viridis(p[i] / 4905.0)
            worst = max(worst, np.abs(img[py, px] - expected).max())
        # 4 levels of 255: the map has 224 levels; one particle row up or down is ~20 off.
        self.assertLess(worst, 4.5)
        # Every wall particle's centre is wall grey.
        for i in np.nonzero(kind == 1)[0]:
            px, py = g.pixel(*x[i])
            if 0 <= px < img.shape[1] and 0 <= py < img.shape[0]:
                self.assertEqual(tuple(img[py, px]), (g.wall_rgb,) * 3, f"wall particle at {x[i]}")
        # The water sits in the tank's lower left corner: the block's right edge is a quarter of
        # the way along the inside of the tank.
        inner_left = g.pixel(0.0, 0.25)[0]
        inner_right = g.pixel(2.0, 0.25)[0]
        self.assertAlmostEqual((g.water_box[2] - inner_left) / (inner_right - inner_left), 0.25, delta=0.02)
        # Empty tank above the water is white.
        px, py = g.pixel(1.0, 0.75)
        self.assertEqual(tuple(img[py, px]), (255, 255, 255))

    def test_fields_have_their_colour_maps(self):
        # At t = 0 the water is at rest: speed 0 is viridis' low end; vx = 0 is the middle of the
        # diverging map, its light grey (221, 221, 221).
        png = self.out("s0.png")
        sluice("render", self.run_dir, "--times", "0", "--range", "0:1", "--size", "800x480", "-o", png)
        img = rgb(png)
        g = Geometry(img, self.frame0)
        x, kind = self.frame0["x"], self.frame0["kind"]
        for i in np.nonzero(kind == 0)[0]:
            px, py = g.pixel(*x[i])
            self.assertEqual(tuple(img[py, px]), (68, 1, 84))
        png = self.out("vx0.png")
        sluice("render", self.run_dir, "--field", "vx", "--times", "0", "--size", "800x480", "-o", png)
        img = rgb(png)
        for i in np.nonzero(kind == 0)[0][::7]:
            px, py = g.pixel(*x[i])
            self.assertLessEqual(np.abs(img[py, px] - 221).max(), 2)
        # Density: denser at the bottom, so lighter on viridis.
        png = self.out("rho0.png")
        sluice("render", self.run_dir, "--field", "density", "--times", "0", "--size", "800x480", "-o", png)
        img = rgb(png)
        bottom = img[g.pixel(0.225, 0.025)[1], g.pixel(0.225, 0.025)[0]]
        top = img[g.pixel(0.225, 0.475)[1], g.pixel(0.225, 0.475)[0]]
        self.assertGreater(bottom.sum(), top.sum() + 100)

    def test_mp4_through_ffmpeg_or_a_clear_message(self):
        mp4 = self.out("a.mp4")
        r = sluice("render", self.run_dir, "--format", "mp4", "-o", mp4, check=False)
        if shutil.which("ffmpeg") is None:
            self.assertEqual(r.returncode, 1)
            self.assertIn("ffmpeg", r.stderr)
            self.assertIn("not installed", r.stderr)
            self.assertFalse(os.path.exists(mp4))
            return
        self.assertEqual(r.returncode, 0, r.stderr)
        probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                                "stream=nb_read_frames,width,height,codec_name,r_frame_rate", "-of",
                                "default=noprint_wrappers=1", mp4], capture_output=True, text=True, check=True)
        info = dict(line.split("=", 1) for line in probe.stdout.split())
        self.assertEqual(int(info["nb_read_frames"]), FRAMES)
        self.assertEqual(info["codec_name"], "h264")
        self.assertEqual(info["r_frame_rate"], "20/1")
        self.assertEqual(int(info["width"]) % 2, 0)

    def assert_3d_picture(self, img, size=None, faint_walls=True, ends=((253, 231, 37), (68, 1, 84))):
        """A picture of a 3D run: water in colour map colours, a colour bar from the map's low end to its
        high end, walls in grey, a white background."""
        if size:
            self.assertEqual((img.shape[1], img.shape[0]), size)
        grey = is_grey(img)
        self.assertGreater((img == 255).all(axis=2).sum(), 0.1 * img.shape[0] * img.shape[1])  # background
        # The colour bar: a column right of the middle whose top is viridis' high end and bottom its low end.
        bar_cols = [x for x in range(img.shape[1] // 2, img.shape[1])
                    if (~grey[:, x]).sum() > img.shape[0] // 3]
        self.assertTrue(bar_cols, "no colour bar")
        col = img[:, bar_cols[len(bar_cols) // 2]]
        coloured = np.nonzero(~is_grey(col[None, :, :])[0])[0]
        self.assertLessEqual(np.abs(col[coloured[0]] - ends[0]).max(), 8)  # top: high end
        self.assertLessEqual(np.abs(col[coloured[-1]] - ends[1]).max(), 8)  # bottom: low end
        # Water: coloured pixels left of the colour bar.
        water = ~grey[:, :min(bar_cols) - 5]
        self.assertGreater(water.sum(), 500)
        # Walls: grey pixels that are neither white nor text-black.
        walls = grey & (img[:, :, 0] > 100) & (img[:, :, 0] < 250)
        self.assertGreater(walls.sum(), 500)
        if faint_walls:
            values, counts = np.unique(img[walls][:, 0], return_counts=True)
            self.assertGreater(values[np.argmax(counts)], 170)  # the commonest wall grey is light
        return water

    def test_3d_views_to_png_and_gif(self):
        for view in VIEWS:
            png = self.out(f"3d_{view}.png")
            r = sluice("render", self.run3d, "--view", view, "--times", "0.1", "--size", "640x480", "-o", png)
            self.assertIn("1 PNG picture (640x480", r.stdout)
            water = self.assert_3d_picture(rgb(png), (640, 480))
            if view == "iso":  # lit spheres: the water has several shades of its colours
                img = rgb(png)
                self.assertGreater(len(np.unique(img[:, :img.shape[1] * 3 // 4][water[:, :img.shape[1] * 3 // 4]],
                                                 axis=0)), 8)
            gif = self.out(f"3d_{view}.gif")
            sluice("render", self.run3d, "--view", view, "--fps", 10, "-o", gif)
            with Image.open(gif) as im:
                self.assertEqual(im.n_frames, FRAMES_3D)
                self.assertEqual(im.info["duration"], 100)
                self.assertEqual(im.size[0] % 2, 0)
                im.seek(FRAMES_3D - 1)
                self.assert_3d_picture(np.asarray(im.convert("RGB")).astype(int))
        # The default is the iso view; an azimuth and elevation of one's own; vz in 3D.
        sluice("render", self.run3d, "--field", "vz", "--times", "0.1", "-o", self.out("3d_default.png"))
        self.assert_3d_picture(rgb(self.out("3d_default.png")), ends=((180, 4, 38), (59, 76, 192)))  # coolwarm
        sluice("render", self.run3d, "--view", "front", "--azimuth", "-120", "--elevation", "45", "--times", "0.1",
               "-o", self.out("3d_angles.png"))
        self.assert_3d_picture(rgb(self.out("3d_angles.png")))
        # The top view of a tank 0.6 m wide and 0.4 m deep is wider than high; the front view of one
        # 0.8 m high is much narrower.
        with Image.open(self.out("3d_top.gif")) as top, Image.open(self.out("3d_front.gif")) as front:
            self.assertGreater(top.size[0], top.size[1])
            self.assertLess(front.size[0] / front.size[1], 0.8 * top.size[0] / top.size[1])

    def test_3d_slice_to_png_and_gif(self):
        png = self.out("3d_slice.png")
        sluice("render", self.run3d, "--slice", "y=0.1", "--times", "0", "--range", "0:1", "--size", "640x480",
               "-o", png)
        img = rgb(png)
        self.assert_3d_picture(img, (640, 480), faint_walls=False)
        # Drawn as a 2D run: walls in the 2D wall grey, the water at rest in viridis' low end.
        self.assertGreater(((img == 145).all(axis=2)).sum(), 500)
        self.assertGreater(((img == (68, 1, 84)).all(axis=2)).sum(), 500)
        gif = self.out("3d_slice.gif")
        sluice("render", self.run3d, "--slice", "x=0.1", "--thickness", "0.1", "-o", gif)
        with Image.open(gif) as im:
            self.assertEqual(im.n_frames, FRAMES_3D)
            im.seek(0)
            self.assert_3d_picture(np.asarray(im.convert("RGB")).astype(int), faint_walls=False)

    def test_3d_flags_errors(self):
        def fails(run, *args, says):
            r = sluice("render", run, *args, "-o", self.out("never.gif"), check=False)
            self.assertEqual(r.returncode, 2, f"{args}: {r.stderr}")
            self.assertIn(says, r.stderr)
            self.assertFalse(os.path.exists(self.out("never.gif")))
        # Camera and slice flags, and vz, on a 2D run.
        fails(self.run_dir, "--view", "iso", says="--view: the run is 2D")
        fails(self.run_dir, "--azimuth", "30", says="--azimuth: the run is 2D")
        fails(self.run_dir, "--elevation", "30", says="--elevation: the run is 2D")
        fails(self.run_dir, "--slice", "y=0.5", says="--slice: the run is 2D")
        fails(self.run_dir, "--field", "vz", says="--field vz: the run is 2D")
        # Bad values on a 3D run.
        fails(self.run3d, "--view", "perspective", says="unknown view")
        fails(self.run3d, "--elevation", "95", says="--elevation 95")
        fails(self.run3d, "--azimuth", "east", says="--azimuth 'east'")
        fails(self.run3d, "--slice", "w=0.1", says="--slice 'w=0.1'")
        fails(self.run3d, "--slice", "y=2", says="outside the run")
        fails(self.run3d, "--slice", "y=0.2", "--thickness", "0.001", "--times", "0", says="no particle lies within")
        fails(self.run3d, "--slice", "y=0.2", "--thickness", "-1", says="--thickness '-1'")
        fails(self.run3d, "--thickness", "0.1", says="--thickness")
        fails(self.run3d, "--slice", "y=0.2", "--view", "top", says="--view and --slice")

    def test_errors_are_clear(self):
        r = sluice("render", self.run_dir, "--field", "velocity", check=False)
        self.assertEqual(r.returncode, 2)
        self.assertIn("unknown field 'velocity'", r.stderr)
        empty = self.out("empty")
        os.makedirs(empty, exist_ok=True)
        r = sluice("render", empty, check=False)
        self.assertEqual(r.returncode, 2)
        self.assertIn("no frames", r.stderr)
        r = sluice("render", self.run_dir, "--range", "5:1", check=False)
        self.assertEqual(r.returncode, 2)
        self.assertIn("--range", r.stderr)
        r = sluice("run", "--render", "nope", "-o", self.out("never"), check=False)
        self.assertEqual(r.returncode, 2)  # refused before the run
        self.assertIn("unknown field 'nope'", r.stderr)
        self.assertFalse(os.path.exists(self.out("never")))

        broken = self.out("broken")
        shutil.copytree(self.run_dir, broken)
        frame = os.path.join(broken, "frames", "frame_000002.npz")
        with open(frame, "r+b") as f:
            f.truncate(300)
        r = sluice("render", broken, "-o", self.out("broken.gif"), check=False)
        self.assertEqual(r.returncode, 1)
        self.assertIn("frame_000002.npz", r.stderr)
        self.assertFalse(os.path.exists(self.out("broken.gif")))
        os.remove(frame)
        r = sluice("render", broken, check=False)
        self.assertEqual(r.returncode, 1)
        self.assertIn("frame 2 is missing", r.stderr)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--sluice", required=True)
    args, rest = parser.parse_known_args()
    SLUICE = os.path.abspath(args.sluice)
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
