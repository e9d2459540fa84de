"""The baxter factory."""
