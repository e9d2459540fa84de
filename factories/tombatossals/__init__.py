"""The tombatossals factory."""
