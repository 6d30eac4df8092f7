"""Studies built from cases: one study expansion, Hertz/JKR verification, stability suite, convergence study."""
