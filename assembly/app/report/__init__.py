"""What each command writes: the ``flexgear run`` pipeline and its HTML report
(:mod:`.pipeline`, :mod:`.html`, the tables of :mod:`.tables` and :mod:`.static_tables`,
the key modes :mod:`.key_modes`, the report's FRF :mod:`.run_frf`), and the files and
summaries of ``flexgear frf``, ``simulate``, ``campbell`` and ``part`` (:mod:`.frf`,
:mod:`.simulate`, :mod:`.campbell`, :mod:`.part`)."""
