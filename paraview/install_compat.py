"""Install (or remove) the ParaView 5.11 / Python 3.11 plugin shim into ParaView's Python site directory.

    python3 paraview/install_compat.py [--user | --target DIR] [--uninstall | --check]

Run it with the Python that ParaView embeds (Debian's ParaView uses the system python3; ``pvpython
install_compat.py`` works everywhere). It copies ``shim/varsph_paraview_compat.py`` and writes
``varsph_paraview_compat.pth`` (one line: ``import varsph_paraview_compat``) into the first writable
site-packages directory (``/usr/local/lib/python3.X/dist-packages`` as root), else into the user site
(``~/.local/lib/python3.X/site-packages``; ``--user`` forces it; ``PYTHONUSERBASE`` moves it). Python runs
``.pth`` import lines at start-up, so the shim is active in the GUI, pvpython and pvbatch before any plugin
loads; see the shim's docstring. Nothing is installed where it is not needed: on Python < 3.11 or a
ParaView whose ``inspect`` use is already fine, the installed hook does nothing.
Exit status 0 on success (``--check``: 0 when installed and current, 1 when not).
"""
import argparse
import filecmp
import os
import shutil
import site
import sys

NAME = "varsph_paraview_compat"
SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "shim", NAME + ".py")
PTH_LINE = "import %s\n" % NAME


def _writable(d):
    probe = d
    while probe and not os.path.exists(probe):
        probe = os.path.dirname(probe)
    return bool(probe) and os.access(probe, os.W_OK)


def target_dir(user=False, target=None):
    if target:
        return target
    if not user:
        for d in site.getsitepackages() if hasattr(site, "getsitepackages") else []:
            if _writable(d):
                return d
    return site.getusersitepackages()


def installed(d):
    mod, pth = os.path.join(d, NAME + ".py"), os.path.join(d, NAME + ".pth")
    if not (os.path.isfile(mod) and os.path.isfile(pth)):
        return False
    with open(pth) as f:
        return filecmp.cmp(SOURCE, mod, shallow=False) and f.read() == PTH_LINE


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--user", action="store_true", help="install into the user site directory")
    ap.add_argument("--target", default=None, help="install into this directory (tests)")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--uninstall", action="store_true")
    g.add_argument("--check", action="store_true", help="exit 0 when installed and current")
    a = ap.parse_args(argv)
    d = target_dir(a.user, a.target)
    if a.check:
        ok = installed(d)
        print("%s: %s in %s" % (NAME, "installed" if ok else "not installed (or outdated)", d))
        return 0 if ok else 1
    if a.uninstall:
        for ext in (".py", ".pth"):
            p = os.path.join(d, NAME + ext)
            if os.path.exists(p):
                os.remove(p)
                print("removed", p)
        return 0
    try:
        os.makedirs(d, exist_ok=True)
        shutil.copyfile(SOURCE, os.path.join(d, NAME + ".py"))
        with open(os.path.join(d, NAME + ".pth"), "w") as f:
            f.write(PTH_LINE)
    except OSError as e:
        print("install_compat: cannot write %s: %s (try --user)" % (d, e), file=sys.stderr)
        return 4
    print("installed %s (.py + .pth) in %s" % (NAME, d))
    return 0


if __name__ == "__main__":
    sys.exit(main())
