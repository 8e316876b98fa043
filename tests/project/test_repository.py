"""The repository holds sources only: no file that .gitignore names (a log, a build, a cache) is tracked,
so scratch a run leaves behind (MuJoCo's MUJOCO_LOG.TXT, say) can never be committed again."""
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_no_tracked_file_is_one_gitignore_names():
    tracked_but_ignored = subprocess.run(["git", "ls-files", "--cached", "--ignored", "--exclude-standard"], cwd=ROOT,
                                         capture_output=True, text=True, check=True).stdout.split()
    assert tracked_but_ignored == []
