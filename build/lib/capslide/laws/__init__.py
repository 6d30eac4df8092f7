"""Physics laws as pure vectorized functions: contact tractions, friction thresholds, the bulk, closed forms."""
