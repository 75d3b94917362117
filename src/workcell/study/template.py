"""The commented study file ``workcell study --defaults`` prints (it loads as the default
study: a test holds them together)."""

TEMPLATE = """# A Workcell study. `workcell study FILE` checks it and prints every plan.
# Every participant runs every condition, in a counterbalanced order; in each condition
# they run the steps below in turn, each step one recorded session. Their sessions carry
# their participant id (p01, p02, ...) as operator id and the condition's name as
# condition: `workcell audit --by condition` compares the conditions, `--by operator`
# the participants (with their learning curves).

# the study's name: 1 to 64 letters, digits, '.', '_' or '-'
name = "study"
# how many participants the plan holds
participants = 12
# order of the conditions: latin_square (balanced: every condition comes first equally
# often and follows every other equally often), fixed (as listed) or shuffled (each
# participant's own order, from the seed)
order = "latin_square"
# study seed: participant k's session of step s has seed + 1000 k + s, the same in every
# condition, so that each participant meets the same worlds in every condition
seed = 0
# what participants read before their first trial
instructions = ""
# the consent text participants accept before their first trial
consent = ""
# days each participant's invite link opens their session once issued (0: it never
# expires); past it their link is refused, saying so: raise it and restart the server, or
# delete their line from the invites file (beside the store) to issue them a new link
invite_days = 0

# Settings every session of the study starts from, as `workcell config --defaults`
# prints them (operator_id, condition, consent, study_step, seed, task.mode and
# task.trials are the study's).
[session]

# One table per condition: its name and the session settings it changes.
[[conditions]]
name = "assisted"
settings = { "world.grasp" = "assisted" }

[[conditions]]
name = "physical"
settings = { "world.grasp" = "physical" }

# What a participant does in each condition, in order, each step one session. mode:
# practice (one trial), collection (`trials` trials) or challenge (task.rounds rounds).
[[steps]]
mode = "practice"
trials = 1

[[steps]]
mode = "collection"
trials = 10
"""
