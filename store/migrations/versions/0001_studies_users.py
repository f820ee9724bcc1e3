"""Studies with their rows and leases; users and their API tokens.

A study file written before migrations existed (tables ``studies`` and ``rows``, no version) is taken over as it
is: its rows table renamed and the lease columns added, every finished row kept.
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0001"
down_revision = None
branch_labels = None
depends_on = None


def upgrade() -> None:
    existing = set(sa.inspect(op.get_bind()).get_table_names())
    if "studies" in existing:
        with op.batch_alter_table("studies") as batch:
            batch.add_column(sa.Column("lease_owner", sa.String(200)))
            batch.add_column(sa.Column("lease_expires", sa.Float))
    else:
        op.create_table(
            "studies",
            sa.Column("id", sa.String(32), primary_key=True),
            sa.Column("spec", sa.Text, nullable=False),
            sa.Column("total", sa.Integer, nullable=False),
            sa.Column("state", sa.String(16), nullable=False),
            sa.Column("created_at", sa.Float, nullable=False),
            sa.Column("run_started_at", sa.Float),
            sa.Column("run_start_done", sa.Integer, nullable=False, server_default="0"),
            sa.Column("elapsed_s", sa.Float, nullable=False, server_default="0"),
            sa.Column("message", sa.Text),
            sa.Column("lease_owner", sa.String(200)),
            sa.Column("lease_expires", sa.Float),
        )
    if "rows" in existing:
        op.rename_table("rows", "study_rows")
    else:
        op.create_table(
            "study_rows",
            sa.Column("study_id", sa.String(32), sa.ForeignKey("studies.id"), primary_key=True),
            sa.Column("idx", sa.Integer, primary_key=True, autoincrement=False),
            sa.Column("params", sa.Text, nullable=False),
            sa.Column("metrics", sa.Text),
            sa.Column("feasible", sa.Boolean),
            sa.Column("problem_type", sa.String(100)),
            sa.Column("detail", sa.Text),
        )
    op.create_index("ix_studies_created_at", "studies", ["created_at"])
    op.create_table(
        "users",
        sa.Column("id", sa.Integer, primary_key=True),
        sa.Column("name", sa.String(100), nullable=False, unique=True),
        sa.Column("password_hash", sa.String(500)),
        sa.Column("roles", sa.String(500), nullable=False, server_default=""),
        sa.Column("created_at", sa.Float, nullable=False),
    )
    op.create_table(
        "api_tokens",
        sa.Column("id", sa.Integer, primary_key=True),
        sa.Column("token_hash", sa.String(128), nullable=False, unique=True),
        sa.Column("user_id", sa.Integer, sa.ForeignKey("users.id", ondelete="CASCADE"), nullable=False),
        sa.Column("label", sa.String(200)),
        sa.Column("created_at", sa.Float, nullable=False),
        sa.Column("last_used_at", sa.Float),
    )
    op.create_index("ix_api_tokens_user_id", "api_tokens", ["user_id"])


def downgrade() -> None:
    op.drop_table("api_tokens")
    op.drop_table("users")
    op.drop_index("ix_studies_created_at", "studies")
    op.drop_table("study_rows")
    op.drop_table("studies")
