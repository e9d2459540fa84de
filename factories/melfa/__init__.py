"""The melfa robot: its factory (factory.py) and its physical description (description.py)."""
