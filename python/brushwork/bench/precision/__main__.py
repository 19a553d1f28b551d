"""`python -m brushwork.bench.precision`: the benchmark on its own."""
import sys

from . import main

sys.exit(main())
