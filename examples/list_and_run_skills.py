#!/usr/bin/env python3
"""List the skills skilld serves, then run a few of them back to back.

    PYTHONPATH=build/python python3 examples/list_and_run_skills.py --skills 0 6 10 --seconds 4

Ctrl-C stops the robot.
"""
import argparse

import flsd

parser = argparse.ArgumentParser(description="List the skills, then run some.")
parser.add_argument("--domain", type=int, default=0, help="DDS domain of skilld")
parser.add_argument("--partition", default="flsd", help="DDS partition of skilld")
parser.add_argument("--skills", type=int, nargs="+", default=[0, 6, 10], help="skill ids to run, in order")
parser.add_argument("--seconds", type=float, default=4.0, help="how long each skill runs")
args = parser.parse_args()

client = flsd.Client(domain=args.domain, partition=args.partition)
print("skill  vx m/s  vy m/s  wz rad/s  survival")
for s in client.list_skills():
    print(f"{s.id:5d}  {s.linear_velocity[0]:6.2f}  {s.linear_velocity[1]:6.2f}  {s.angular_velocity[2]:8.2f}"
          f"  {s.survival_steps:8d}")

with client as robot:  # takes control for the block, and releases it after
    robot.stand()  # each skill starts from a stand the server has verified
    for k in args.skills:
        task = robot.execute_skill(k, args.seconds)
        task.wait()
        result = task.progress()
        x, y, _ = robot.state().position
        print(f"execute_skill {k}: {result.state}: {result.message}; the robot is at ({x:.2f}, {y:.2f})")
