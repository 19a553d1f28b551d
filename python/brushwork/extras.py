"""The optional extras (pyproject.toml's optional-dependencies): how a user adds one.

brushwork installs from its source folder (install.sh makes .venv there and pip-installs the
folder), so an extra is added the same way: the folder with the extra named in brackets."""
from __future__ import annotations


def install_hint(extra: str) -> str:
    """The command that adds `extra` to an install made by install.sh."""
    return f"in brushwork's folder, .venv/bin/pip install '.[{extra}]'"
