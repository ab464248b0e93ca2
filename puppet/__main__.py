from puppet.commands import main

raise SystemExit(main())
