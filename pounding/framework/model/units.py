"""Physical constants the package uses, each written once."""

#: standard gravity [m/s2] (a record in g is scaled by it; a reference that uses 9.81 differs by 3.4e-4)
G = 9.80665
