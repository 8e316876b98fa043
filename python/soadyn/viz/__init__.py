"""Drawing models: the Visual description loaders keep (visuals.py) and the viser viewer (viewer.py)."""
