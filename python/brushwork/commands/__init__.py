"""The top-level commands whose work no one package owns: render, batch, params, gallery and demo.
Each module exports add_arguments(parser) and handle(args); `brushwork.cli` lists them beside the
commands that live in their packages (font/cli.py, outline3d/command.py, paint/commands.py) and the
benchmarks (bench/<name>.py)."""
