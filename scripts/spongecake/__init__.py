"""SpongeCake's multiple-scattering approximation (Wang et al. 2022, Sec. 5):
torch_model (differentiable single scattering and lobes), dataset (entries of
an mcref dataset file), fit (per-material fit of the lobe parameters)."""
