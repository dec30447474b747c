"""Where generated meshes and reductions go: --cache-dir, FLEXGEAR_CACHE_DIR, else the
user's cache folder (XDG Base Directory Specification); tests never use the user's."""
import os
from pathlib import Path

from assembly.model.components import CacheDirs, default_cache_root


def test_default_is_the_users_cache_folder(monkeypatch, tmp_path):
    monkeypatch.delenv("FLEXGEAR_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert default_cache_root() == tmp_path / "xdg" / "flexgear"
    assert CacheDirs().superelements == tmp_path / "xdg" / "flexgear" / "cms"
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/dir")       # the spec: ignore a relative path
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert default_cache_root() == tmp_path / "home" / ".cache" / "flexgear"
    monkeypatch.delenv("XDG_CACHE_HOME")
    assert default_cache_root() == tmp_path / "home" / ".cache" / "flexgear"
    monkeypatch.setenv("FLEXGEAR_CACHE_DIR", str(tmp_path / "env"))
    assert default_cache_root() == tmp_path / "env"


def test_test_session_does_not_use_the_users_cache():
    root = default_cache_root()
    assert root != Path.home() / ".cache" / "flexgear"
    assert os.environ["FLEXGEAR_CACHE_DIR"] == str(root)


def test_cli_cache_dir_option_is_used_and_restored(monkeypatch, tmp_path):
    from assembly.app import cli
    seen = []
    monkeypatch.setattr(cli, "cmd_modes", lambda args: seen.append(default_cache_root()) or 0)
    before = os.environ.get("FLEXGEAR_CACHE_DIR")
    assert cli.main(["--cache-dir", str(tmp_path / "c"), "modes", "kahraman_beta20.toml"]) == 0
    assert seen == [tmp_path / "c"]
    assert os.environ.get("FLEXGEAR_CACHE_DIR") == before
