"""The suite's one conftest. Test modules sit in folders that mirror the package (dynamics/, io/, loops/, ...)
and are imported by pytest with --import-mode=importlib (pyproject.toml), so two folders may hold modules
of the same name and no folder needs an __init__.py. What tests share is imported from this folder:
support/ (builders, oracle mappings, fixtures) and fuzz/ (the fuzz cases), as `from support.trees import ...`."""
import shutil
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))


def pytest_configure(config):
    """MuJoCo appends every warning to MUJOCO_LOG.TXT in the working directory. Tests provoke warnings on
    purpose (hostile MJCF, singular inertias), so this process's log goes to a temporary folder, removed
    at the end: a run leaves no log in the tree. MuJoCo still prints each warning, which pytest captures.
    Forked children inherit the setting; with pytest-xdist every worker configures its own."""
    try:
        import mujoco
    except ImportError:
        return
    folder = Path(tempfile.mkdtemp(prefix="soadyn-tests-mujoco-"))
    config.add_cleanup(lambda: shutil.rmtree(folder, ignore_errors=True))
    log = folder / "MUJOCO_LOG.TXT"
    if hasattr(mujoco, "MjLogConfig"):
        settings = mujoco.MjLogConfig.get()
        settings.logfile = str(log)
        settings.set()
    else:  # an older MuJoCo: its warning hook replaces the log file (and the printing)
        def warn(message: str) -> None:
            with log.open("a") as out:
                out.write(f"WARNING: {message}\n")
            print(f"WARNING: {message}")
        mujoco.set_mju_user_warning(warn)
