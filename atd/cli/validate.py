"""`atd validate` and `atd schema`."""
