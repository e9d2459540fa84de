"""Robot factories: one per robot, found through the `atd.factories` entry-point group.

A factory turns abstract primitives and events into the concrete controllers and
conditions of one robot (thesis 7.2.2). See `factories.base` for the interface and
`docs/mapping-tables.md` for what each robot does.
"""
