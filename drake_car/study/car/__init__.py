"""The car checked on its own: settling, kinematics, their figures and report."""
