"""The tombatossals robot: its factory (factory.py) and its physical description (description.py)."""
