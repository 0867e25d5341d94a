"""Physical models: parameter derivation and the glue that calls the pure kernels."""
