import glob
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
# a source tree with its core built in place (a developer's build linked into python/brushwork)
# is what the tests must see, not a brushwork installed earlier into site-packages; a clean
# clone has no core there and tests the installed package, as CI does
SOURCE = os.path.join(os.path.dirname(HERE), "python")
if glob.glob(os.path.join(SOURCE, "brushwork", "_core*.so")):
    sys.path.insert(0, SOURCE)
