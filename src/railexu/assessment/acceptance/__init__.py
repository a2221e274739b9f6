"""Virtual acceptance per EN 14363:2016: the quantities of each test section, their limits by
vehicle category, the statistical evaluation over the sections of a test zone, the programme
files, and the quasi-static tests (safety against derailment on twisted track, the bogie's yaw
resistance). ``docs/acceptance.md`` explains what is computed and from which clause.
"""
