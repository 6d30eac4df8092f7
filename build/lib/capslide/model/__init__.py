"""The discrete cap-on-substrate system: bulk + contact + one load constraint, and its setup from parameters."""
