"""Reading and writing models: URDF (urdf*.py), MJCF (mjcf.py), soadyn's own model files (model_file.py).

The loaders are public as soadyn.load_urdf, soadyn.load_mjcf, soadyn.load_model, soadyn.save_model and
soadyn.save_urdf.
"""
