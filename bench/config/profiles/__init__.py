"""The embedded profiles: the TOML configurations `stripebench run --profile NAME` and the tuning commands read."""
