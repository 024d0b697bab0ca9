"""The import contracts: reference/ and fast/ share no integration code, and the rooms of
cross_check/ import only downwards, with no circle anywhere.

``fast`` may read ``reference.scene`` (the problem definition) and nothing else of
``reference``; ``reference`` never imports ``fast`` or ``cross_check``; in ``cross_check``
the layers run ``__main__ > verify > report | sensitivity | proofs | league > atlas | score | paper > golden >
golden_proof | golden_runs > golden_files > scenefile > scenes | dynamics > agreement > tolerances`` (``|``: neither imports the other), ``dynamics`` knows no scene table; the
league's peer adapters import no integration code of ``reference`` or ``fast``; and no
package has an import circle among its modules.  The contracts live in ``pyproject.toml``
under ``[tool.importlinter]``; this test runs import-linter.
"""
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_import_contracts_hold():
    linter = pathlib.Path(sys.executable).with_name("lint-imports")
    cmd = [str(linter)] if linter.exists() else ["lint-imports"]
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "Contracts: 6 kept, 0 broken" in proc.stdout, proc.stdout


def test_fast_reads_only_the_scene_of_reference():
    """Catch-all beside the named contract: any new reference module is covered too."""
    import grimp

    graph = grimp.build_graph("fast", "reference", "cross_check")
    crossing = {
        (importer, imported)
        for importer in graph.find_descendants("fast") | {"fast"}
        for imported in graph.find_modules_directly_imported_by(importer)
        if imported.split(".")[0] == "reference"
    }
    assert {imported for _, imported in crossing} <= {"reference.scene"}, sorted(crossing)
