"""Nonlinear and linear solvers: Newton with line search; LU-reuse, pyamg and direct sparse solves."""
