#!/usr/bin/env python3
"""Walk to a goal around a map's obstacles, then draw the planned and walked paths as an SVG.

    PYTHONPATH=build/python python3 examples/navigate_and_plot.py --goal 5 0 --map configs/maps/demo.yaml

The map's obstacles are drawn when PyYAML is installed. Exits with 4 if the robot did not get there,
as skillctl does. Ctrl-C stops the robot.
"""
import argparse
import pathlib
import sys

import flsd

parser = argparse.ArgumentParser(description="Navigate, then plot the path.")
parser.add_argument("--domain", type=int, default=0, help="DDS domain of skilld")
parser.add_argument("--partition", default="flsd", help="DDS partition of skilld")
parser.add_argument("--goal", type=float, nargs=2, default=[5.0, 0.0], metavar=("X", "Y"), help="m, world frame")
parser.add_argument("--map", type=pathlib.Path, help="a map's YAML (default: the server's map)")
parser.add_argument("--duration", type=float, default=150.0, help="give up after this many seconds")
parser.add_argument("--picture", type=pathlib.Path, default=pathlib.Path("navigation.svg"))
args = parser.parse_args()

map_yaml = args.map.read_text() if args.map else ""
planned, walked = [], []
with flsd.Client(domain=args.domain, partition=args.partition) as robot:
    robot.stand()
    task = robot.navigate(*args.goal, map_yaml=map_yaml, duration=args.duration)
    tick = 0
    while not task.done():
        s = robot.next_state(tick)
        if s is None:
            continue
        tick = s.tick
        if s.task.request_id == task.request_id:
            path = [tuple(p) for p in s.task.path]
            if path and (not planned or planned[-1] != path):
                planned.append(path)
            if s.mode == flsd.Mode.NAVIGATE:
                walked.append((s.position[0], s.position[1]))
    result = task.progress()
    print(f"navigate: {result.state}: {result.message}")


def obstacles(text):
    """The map's circles and polygons, if PyYAML can read them."""
    try:
        import yaml
    except ImportError:
        return [], []
    m = yaml.safe_load(text) or {}
    return m.get("circles", []), m.get("polygons", [])


circles, polygons = obstacles(map_yaml)
points = walked + [p for path in planned for p in path] + [tuple(args.goal), (0.0, 0.0)]
points += [(c["center"][0] + sx * c["radius"], c["center"][1] + sy * c["radius"]) for c in circles for sx, sy in
           ((-1, -1), (1, 1))] + [tuple(p) for poly in polygons for p in poly]
x0, x1 = min(p[0] for p in points) - 0.5, max(p[0] for p in points) + 0.5
y0, y1 = min(p[1] for p in points) - 0.5, max(p[1] for p in points) + 0.5
scale = 600 / max(x1 - x0, y1 - y0)  # pixels per metre; y points up


def px(p):
    return (p[0] - x0) * scale, (y1 - p[1]) * scale


def xy(p):
    return "{:.1f},{:.1f}".format(*px(p))


def polyline(path, style):
    return f'<polyline points="{" ".join(xy(p) for p in path)}" fill="none" {style}/>'


def disc(center, radius, colour):
    cx, cy = px(center)
    return f'<circle cx="{cx:.1f}" cy="{cy:.1f}" r="{radius:.1f}" fill="{colour}"/>'


shapes = ['<rect width="100%" height="100%" fill="white"/>']
shapes += [disc(c["center"], c["radius"] * scale, "#bbb") for c in circles]
shapes += [f'<polygon points="{" ".join(xy(p) for p in poly)}" fill="#bbb"/>' for poly in polygons]
shapes += [polyline(path, 'stroke="#48c" stroke-dasharray="6 4" stroke-width="1.5"') for path in planned]
if walked:
    shapes.append(polyline(walked, 'stroke="#d40" stroke-width="2.5"'))
shapes.append(disc(args.goal, 6, "#2a2"))
shapes.append(f'<text x="8" y="20" font-family="sans-serif" font-size="14">{result.state}: planned (dashed), '
              f'walked (red), goal (green)</text>')
width, height = (x1 - x0) * scale, (y1 - y0) * scale
args.picture.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}">'
                        + "".join(shapes) + "</svg>\n")
print(f"picture: {args.picture}")
sys.exit(0 if result.state == flsd.TaskState.SUCCEEDED else 4)
