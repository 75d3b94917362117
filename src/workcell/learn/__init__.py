"""Learning from the record: LeRobot's training on an export, and learned policies as
operators that are recorded and audited like every other.

Everything here that trains or runs a policy needs the learn extra (``pip install
'workcell[learn]'``: LeRobot and torch); importing this package does not.
"""
