"""Scene files (TOML): links, materials, mechanisms, motion, loads and what to compute."""
