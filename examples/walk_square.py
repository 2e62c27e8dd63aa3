#!/usr/bin/env python3
"""Walk a square with track_velocity: forward along a side, turn left a quarter, four times.

    PYTHONPATH=build/python python3 examples/walk_square.py --speed 0.3 --side-seconds 4

The skill selector chooses the skills for each command. Ctrl-C stops the robot.
"""
import argparse
import math
import sys

import flsd

parser = argparse.ArgumentParser(description="Walk a square with track_velocity.")
parser.add_argument("--domain", type=int, default=0, help="DDS domain of skilld")
parser.add_argument("--partition", default="flsd", help="DDS partition of skilld")
parser.add_argument("--speed", type=float, default=0.3, help="forward speed, m/s")
parser.add_argument("--side-seconds", type=float, default=4.0, help="how long each side is walked")
parser.add_argument("--turn-rate", type=float, default=1.0, help="rad/s while turning")
args = parser.parse_args()

with flsd.Client(domain=args.domain, partition=args.partition) as robot:
    robot.stand()
    for side in range(4):
        for vx, wz, seconds in ((args.speed, 0.0, args.side_seconds), (0.0, args.turn_rate, math.pi / 2 / args.turn_rate)):
            task = robot.track_velocity(vx, 0.0, wz, seconds)
            task.wait()
            result = task.progress()
            if not task.succeeded:
                print(f"side {side + 1}: {result.state}: {result.message}")
                sys.exit(4)
        s = robot.state()
        print(f"corner {side + 1}: at ({s.position[0]:.2f}, {s.position[1]:.2f}), heading {math.degrees(s.yaw):.0f} deg")
    print("square done")
