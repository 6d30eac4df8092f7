"""Discretization: reference elements, meshes, bulk assembly, the contact surface integral."""
