import sys

from pix2pockets.cli.main import main

sys.exit(main())
