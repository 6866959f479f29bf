# SPDX-License-Identifier: Apache-2.0
from model.cli import main

raise SystemExit(main())
