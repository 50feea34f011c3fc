"""Paper units to SI, applied once at the boundary (builders, validation, figures)."""

MM = 1e-3  # [m]
MM2 = MM**2  # [m^2]
MM3 = MM**3  # [m^3]
GPA = 1e9  # [Pa]
MPA = 1e6  # [Pa]
KN = 1e3  # [N]
KN_M3 = 1e3  # unit weight [N/m^3]
N_MM3 = 1e9  # contact stiffness N/mm^3 -> [Pa/m]
G = 9.81  # standard gravity [m/s^2]
CM = 1e-2  # [m]

LENGTH_UNITS = {"m": 1.0, "cm": CM, "mm": MM}
"""Length units a user's file may be in, as metres per unit (``--units``, TOML ``units``)."""
