"""The melfa factory."""
