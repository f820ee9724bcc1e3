"""Sign-off an office can trust: a deviation's reason and an import's note on each revision, comments on
revisions, at most one approved revision per design (a partial unique index), and a credential epoch on users
and tokens so that a password reset, a removed role or a removed user ends their sessions and tokens."""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0003"
down_revision = "0002"
branch_labels = None
depends_on = None

APPROVED = sa.text("state = 'approved'")


def upgrade() -> None:
    with op.batch_alter_table("revisions") as batch:
        batch.add_column(sa.Column("deviation", sa.Text))
        batch.add_column(sa.Column("imported_note", sa.Text))
    op.create_table(
        "revision_comments",
        sa.Column("id", sa.Integer, primary_key=True),
        sa.Column("revision_id", sa.Integer, sa.ForeignKey("revisions.id"), nullable=False),
        sa.Column("author", sa.String(100), nullable=False),
        sa.Column("created_at", sa.Float, nullable=False),
        sa.Column("kind", sa.String(16), nullable=False),
        sa.Column("text", sa.Text, nullable=False),
    )
    op.create_index("ix_revision_comments_revision_id", "revision_comments", ["revision_id"])
    # A library that approved two revisions of one design before this rule keeps the later one approved.
    op.execute(sa.text(
        "UPDATE revisions SET state = 'superseded', superseded_by = (SELECT max(r2.number) FROM revisions r2 "
        "WHERE r2.design_id = revisions.design_id AND r2.state = 'approved') WHERE state = 'approved' AND number < "
        "(SELECT max(r3.number) FROM revisions r3 WHERE r3.design_id = revisions.design_id AND r3.state = 'approved')"))
    op.create_index("uq_revisions_one_approved", "revisions", ["design_id"], unique=True,
                    sqlite_where=APPROVED, postgresql_where=APPROVED)
    with op.batch_alter_table("users") as batch:
        batch.add_column(sa.Column("credential_epoch", sa.Integer, nullable=False, server_default="0"))
    with op.batch_alter_table("api_tokens") as batch:
        batch.add_column(sa.Column("epoch", sa.Integer, nullable=False, server_default="0"))


def downgrade() -> None:
    with op.batch_alter_table("api_tokens") as batch:
        batch.drop_column("epoch")
    with op.batch_alter_table("users") as batch:
        batch.drop_column("credential_epoch")
    op.drop_index("uq_revisions_one_approved", "revisions")
    op.drop_table("revision_comments")
    with op.batch_alter_table("revisions") as batch:
        batch.drop_column("imported_note")
        batch.drop_column("deviation")
