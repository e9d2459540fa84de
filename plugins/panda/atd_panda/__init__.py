"""The panda robot for atd: `factory.py` maps tasks onto it, `description.py` is its body
(both simulators are built from it), `config.toml` its tuned values."""
